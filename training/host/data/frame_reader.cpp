// Frame sequences on disk (frame_reader.h).
#include "s4d/data/frame_reader.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "s4d/data/video_reader.h"

namespace s4d::data {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const fs::path& p, const std::string& why) { throw std::runtime_error(p.string() + ": " + why); }

std::string lower_extension(const fs::path& p) {
  std::string s = p.extension().string();
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// A PNG of 1 to 4 channels as RGB: gray replicated, alpha dropped.
io::ImageF rgb(io::ImageF im, const fs::path& p) {
  if (im.channels == 3) return im;
  if (im.channels < 1 || im.channels > 4) fail(p, std::to_string(im.channels) + " channels, expected 1 to 4");
  const bool gray = im.channels <= 2;
  const size_t pixels = size_t(im.width) * size_t(im.height), c = size_t(im.channels);
  io::ImageF out{im.width, im.height, 3, std::vector<float>(pixels * 3)};
  for (size_t i = 0; i < pixels; ++i)
    for (size_t k = 0; k < 3; ++k) out.data[i * 3 + k] = im.data[i * c + (gray ? 0 : k)];
  return out;
}

}  // namespace

bool is_video_path(const fs::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".mp4" || ext == ".avi" || ext == ".mov" || ext == ".mkv";
}

std::vector<fs::path> png_frames(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && lower_extension(entry.path()) == ".png") files.push_back(entry.path());
  if (files.empty()) fail(folder, "no PNG frames in the folder");
  std::sort(files.begin(), files.end());
  return files;
}

FrameReader::FrameReader(const fs::path& path) : path_(path) {
  if (fs::is_directory(path)) {
    pngs_ = png_frames(path);
    count_ = int(pngs_.size());
    return;
  }
  if (!fs::exists(path)) fail(path, "no such folder or video");
  if (!is_video_path(path)) fail(path, "neither a folder of PNG frames nor a video (.mp4, .avi, .mov, .mkv)");
  video_ = std::make_unique<VideoReader>(path);
  count_ = video_->info().frames;
}

FrameReader::~FrameReader() = default;

std::optional<io::ImageF> FrameReader::next() {
  std::optional<io::ImageF> frame;
  fs::path where = path_;
  if (video_) {
    frame = video_->next();
    where += " frame " + std::to_string(next_);
  } else if (size_t(next_) < pngs_.size()) {
    where = pngs_[size_t(next_)];
    frame = rgb(io::read_png(where), where);
  }
  if (!frame) return frame;
  if (next_++ == 0) width_ = frame->width, height_ = frame->height;
  if (frame->width != width_ || frame->height != height_)
    fail(where, std::to_string(frame->width) + "x" + std::to_string(frame->height) + ", but the first frame is " +
                    std::to_string(width_) + "x" + std::to_string(height_));
  return frame;
}

io::ImageF FrameReader::next_counted() {
  std::optional<io::ImageF> frame = next();
  if (!frame) fail(path_, "ends after " + std::to_string(next_) + " of the " + std::to_string(count_) + " frames declared");
  return std::move(*frame);
}

}  // namespace s4d::data
