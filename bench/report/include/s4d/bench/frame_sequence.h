// The frames of one video to score: a folder of PNG files (in file-name order) or a video file
// (s4d/data/video_reader.h), read front to back as RGB [H, W, 3] in [0, 1]. Alpha
// in RGBA PNGs is dropped.
#pragma once
#include <filesystem>
#include <memory>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::data {
class VideoReader;
}

namespace s4d::bench {

class FrameSequence {
 public:
  // Throws std::runtime_error naming the path when it is missing, a folder without PNG files, or a
  // video that cannot be opened.
  explicit FrameSequence(const std::filesystem::path& path);
  ~FrameSequence();
  FrameSequence(const FrameSequence&) = delete;
  FrameSequence& operator=(const FrameSequence&) = delete;

  int size() const { return count_; }
  const std::filesystem::path& path() const { return path_; }
  // The next frame; throws std::runtime_error naming the file and frame when it cannot be read or
  // none is left.
  io::ImageF next();

 private:
  std::filesystem::path path_;
  std::vector<std::filesystem::path> pngs_;
  std::unique_ptr<data::VideoReader> video_;
  int count_ = 0, next_ = 0;
};

}  // namespace s4d::bench
