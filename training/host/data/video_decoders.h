// One open VideoReader per video of a dataset, so that reading each video's frames in order never
// seeks (frame_cache.h, background.cpp).
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>

#include "s4d/data/video_reader.h"

namespace s4d::data::detail {

class VideoDecoders {
 public:
  VideoDecoders();
  ~VideoDecoders();
  VideoDecoders(const VideoDecoders&) = delete;
  VideoDecoders& operator=(const VideoDecoders&) = delete;

  // Frame `frame` (from 0) of the video (VideoReader::read). After a failure the reader's position
  // is unknown, so it is closed: the next read of that video reopens it.
  io::ImageF read(const std::filesystem::path& path, int frame);

 private:
  std::unordered_map<std::string, std::unique_ptr<VideoReader>> open_;  // by path
};

}  // namespace s4d::data::detail
