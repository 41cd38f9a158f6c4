#include "s4d/data/video_reader.h"

#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "dataset_parts.h"
#include "video_plugin/video_plugin.h"

namespace s4d::data {

using detail::fail;

namespace {

// A seek lands on the keyframe before the target and decodes forward from it, so for a short jump
// ahead decoding the frames in between is no slower. 16 covers FFmpeg's default keyframe interval
// (12 frames) for MPEG-4 Part 2.
constexpr int kMaxForwardDecode = 16;

// Bound on a declared size or frame count, far beyond real videos, so a corrupt header cannot
// overflow the conversion to int.
constexpr double kMaxCount = 1 << 24;

}  // namespace

struct VideoReader::Capture {
  std::unique_ptr<video_plugin::Capture> capture;
};

VideoReader::VideoReader(const std::filesystem::path& path) : path_(path) {
  if (!std::filesystem::exists(path)) fail(path, "video does not exist");
  const std::string name = path.string();
  video_plugin::Capture* capture = video_plugin::api(name.c_str()).open_capture(name.c_str());
  capture_ = std::make_unique<Capture>(Capture{std::unique_ptr<video_plugin::Capture>(capture)});
  if (!capture_->capture) fail(path, "cannot open the video (not a video file, corrupt, or no decoder for its codec)");
}

VideoReader::~VideoReader() = default;

VideoInfo VideoReader::info() const {
  // OpenCV reports the properties as doubles (0 when unknown); range-check before converting.
  const video_plugin::Capture& capture = *capture_->capture;
  const double width = capture.width(), height = capture.height();
  const double frames = capture.frame_count();
  if (!(width >= 1 && width <= kMaxCount && height >= 1 && height <= kMaxCount)) {
    fail(path_, "video declares no valid frame size");
  }
  if (!(frames >= 1 && frames <= kMaxCount)) fail(path_, "video declares no valid frame count");
  return {static_cast<int>(width), static_cast<int>(height), static_cast<int>(frames)};
}

std::optional<io::ImageF> VideoReader::next() {
  cv::Mat bgr;
  if (!capture_->capture->read(bgr) || bgr.empty()) return std::nullopt;
  const int frame = next_++;
  if (bgr.type() != CV_8UC3) {
    fail(path_, "frame " + std::to_string(frame) + " decodes to an unsupported pixel format (expected 8-bit BGR)");
  }
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::Mat values;
  rgb.convertTo(values, CV_32FC3, 1.0 / 255.0);  // a new, continuous matrix
  io::ImageF image{values.cols, values.rows, 3, {}};
  image.data.resize(values.total() * 3);
  std::memcpy(image.data.data(), values.ptr<float>(), image.data.size() * sizeof(float));
  return image;
}

io::ImageF VideoReader::read(int frame) {
  const std::string what = "frame " + std::to_string(frame);
  if (frame < next_ || frame > next_ + kMaxForwardDecode) {
    if (!capture_->capture->seek(frame)) fail(path_, what + " cannot be reached (seek failed)");
    next_ = frame;
  }
  for (; next_ < frame; ++next_) {
    if (!capture_->capture->grab()) fail(path_, what + " cannot be decoded (the video ends or is corrupt before it)");
  }
  std::optional<io::ImageF> image = next();
  if (!image) fail(path_, what + " cannot be decoded (past the end of the video, or corrupt)");
  return std::move(*image);
}

VideoInfo probe_video(const std::filesystem::path& path) { return VideoReader(path).info(); }

}  // namespace s4d::data
