// Where a sequence's frames go: numbered PNGs (RGB over the background), numbered EXRs (R, G, B,
// A = accumulated alpha, Z = expected depth), or one mp4 video (OpenCV, mp4v, lossy). Private to
// s4d_protocols.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"
#include "s4d/protocols/protocol_render.h"

namespace s4d::protocols {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Writes frame `index`; returns its file name relative to the sequence folder ("" inside a video).
  virtual std::string write(int index, const io::ImageF& rgb, const std::vector<float>& alpha,
                            const std::vector<float>& depth) = 0;
};

// `frames`: the sequence length (sets the zero padding, at least 4 digits, so names sort in order).
std::unique_ptr<FrameSink> make_frame_sink(Format format, const std::filesystem::path& dir, int width, int height,
                                           int frames, double fps);

}  // namespace s4d::protocols
