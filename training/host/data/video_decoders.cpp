#include "video_decoders.h"

namespace s4d::data::detail {

VideoDecoders::VideoDecoders() = default;
VideoDecoders::~VideoDecoders() = default;

io::ImageF VideoDecoders::read(const std::filesystem::path& path, int frame) {
  std::unique_ptr<VideoReader>& slot = open_[path.string()];
  try {
    if (!slot) slot = std::make_unique<VideoReader>(path);
    return slot->read(frame);
  } catch (...) {
    open_.erase(path.string());
    throw;
  }
}

}  // namespace s4d::data::detail
