#include "s4d/bench/frame_sequence.h"

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <stdexcept>

namespace s4d::bench {

struct FrameSequence::Video {
  cv::VideoCapture capture;
};

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
  video_ = std::make_unique<Video>(Video{cv::VideoCapture(path.string(), cv::CAP_FFMPEG)});
  if (!video_->capture.isOpened()) fail(path, "cannot open the video (not a video file, corrupt, or no decoder for its codec)");
  const double frames = video_->capture.get(cv::CAP_PROP_FRAME_COUNT);
  if (!(frames >= 1 && frames < double(1 << 24))) fail(path, "video declares no valid frame count");
  count_ = int(frames);
}

FrameSequence::~FrameSequence() = default;

io::ImageF FrameSequence::next() {
  if (next_ >= count_) fail(path_, "no frame left after " + std::to_string(count_));
  const int index = next_++;
  if (!video_) return rgb_only(io::read_png(pngs_[size_t(index)]), pngs_[size_t(index)]);
  cv::Mat bgr, rgb, values;
  if (!video_->capture.read(bgr) || bgr.empty() || bgr.type() != CV_8UC3)
    fail(path_, "frame " + std::to_string(index) + " cannot be decoded as 8-bit colour");
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  rgb.convertTo(values, CV_32FC3, 1.0 / 255.0);
  io::ImageF im{values.cols, values.rows, 3, {}};
  im.data.assign(values.ptr<float>(), values.ptr<float>() + values.total() * 3);
  return im;
}

}  // namespace s4d::bench
