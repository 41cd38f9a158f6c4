#include "s4d/bench/frame_sequence.h"

#include <algorithm>
#include <stdexcept>

#include "s4d/data/video_reader.h"

namespace s4d::bench {

namespace {
[[noreturn]] void fail(const std::filesystem::path& p, const std::string& why) { throw std::runtime_error(p.string() + ": " + why); }

io::ImageF rgb_only(io::ImageF im, const std::filesystem::path& p) {
  if (im.channels == 3) return im;
  if (im.channels != 4) fail(p, "expected an RGB or RGBA PNG, got " + std::to_string(im.channels) + " channels");
  io::ImageF out{im.width, im.height, 3, std::vector<float>(size_t(im.width) * im.height * 3)};
  for (size_t i = 0; i < size_t(im.width) * im.height; ++i)
    for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = im.data[i * 4 + c];
  return out;
}
}  // namespace

FrameSequence::FrameSequence(const std::filesystem::path& path) : path_(path) {
  if (!std::filesystem::exists(path)) fail(path, "does not exist (expected a folder of PNG frames or a video file)");
  if (std::filesystem::is_directory(path)) {
    for (const auto& e : std::filesystem::directory_iterator(path))
      if (e.is_regular_file() && e.path().extension() == ".png") pngs_.push_back(e.path());
    std::sort(pngs_.begin(), pngs_.end());
    if (pngs_.empty()) fail(path, "folder holds no .png frames");
    count_ = int(pngs_.size());
    return;
  }
  video_ = std::make_unique<data::VideoReader>(path);
  count_ = video_->info().frames;
}

FrameSequence::~FrameSequence() = default;

io::ImageF FrameSequence::next() {
  if (next_ >= count_) fail(path_, "no frame left after " + std::to_string(count_));
  const int index = next_++;
  if (!video_) return rgb_only(io::read_png(pngs_[size_t(index)]), pngs_[size_t(index)]);
  return video_->read(index);
}

}  // namespace s4d::bench
