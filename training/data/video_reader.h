// Frames of the DyNeRF / Neu3D camNN.mp4 videos, decoded through OpenCV's FFmpeg backend. OpenCV
// stays behind this private header: no public header of s4d_data includes it.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>

#include "s4d/io/image_io.h"

namespace s4d::data::detail {

struct VideoInfo {
  int width = 0, height = 0;
  int frames = 0;  // as the container declares it; decoding a frame past the real end fails then
};

// Throws std::runtime_error("<path>: ...") when the video cannot be opened or declares no frames.
VideoInfo probe_video(const std::filesystem::path& path);

// One open decoder per video, each remembering the frame it decodes next, so that reading a video's
// frames in order never seeks; any other order seeks or decodes forward.
class VideoDecoders {
 public:
  VideoDecoders();
  ~VideoDecoders();
  VideoDecoders(const VideoDecoders&) = delete;
  VideoDecoders& operator=(const VideoDecoders&) = delete;

  // Frame `frame` (from 0) of the video as RGB float [H, W, 3] in [0, 1]. Throws std::runtime_error
  // naming the file when it cannot be opened or the frame cannot be decoded.
  io::ImageF read(const std::filesystem::path& path, int frame);

 private:
  struct Decoder;
  std::unordered_map<std::string, std::unique_ptr<Decoder>> open_;  // by path
};

}  // namespace s4d::data::detail
