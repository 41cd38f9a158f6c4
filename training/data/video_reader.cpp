#include "video_reader.h"

#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "dataset_parts.h"

namespace s4d::data::detail {
namespace {

// A seek lands on the keyframe before the target and decodes forward from it, so for a short jump
// ahead decoding the frames in between is no slower. 16 covers FFmpeg's default keyframe interval
// (12 frames) for MPEG-4 Part 2.
constexpr int kMaxForwardDecode = 16;

// Bound on a declared size or frame count, far beyond real videos, so a corrupt header cannot
// overflow the conversion to int.
constexpr double kMaxCount = 1 << 24;

// The FFmpeg backend, named: left to choose, OpenCV also tries GStreamer, which prints warnings for
// every file it cannot open.
cv::VideoCapture open_capture(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) fail(path, "video does not exist");
  cv::VideoCapture capture(path.string(), cv::CAP_FFMPEG);
  if (!capture.isOpened()) fail(path, "cannot open the video (not a video file, corrupt, or no decoder for its codec)");
  return capture;
}

}  // namespace

VideoInfo probe_video(const std::filesystem::path& path) {
  cv::VideoCapture capture = open_capture(path);
  // OpenCV reports the properties as doubles (0 when unknown); range-check before converting.
  const double width = capture.get(cv::CAP_PROP_FRAME_WIDTH), height = capture.get(cv::CAP_PROP_FRAME_HEIGHT);
  const double frames = capture.get(cv::CAP_PROP_FRAME_COUNT);
  if (!(width >= 1 && width <= kMaxCount && height >= 1 && height <= kMaxCount)) {
    fail(path, "video declares no valid frame size");
  }
  if (!(frames >= 1 && frames <= kMaxCount)) fail(path, "video declares no valid frame count");
  return {static_cast<int>(width), static_cast<int>(height), static_cast<int>(frames)};
}

struct VideoDecoders::Decoder {
  cv::VideoCapture capture;
  int next = 0;  // the frame the next read() decodes
};

VideoDecoders::VideoDecoders() = default;
VideoDecoders::~VideoDecoders() = default;

io::ImageF VideoDecoders::read(const std::filesystem::path& path, int frame) {
  std::unique_ptr<Decoder>& slot = open_[path.string()];
  if (!slot) slot = std::make_unique<Decoder>(Decoder{open_capture(path), 0});
  Decoder& d = *slot;
  const std::string what = "frame " + std::to_string(frame);
  // After a failure the decoder's position is unknown: drop it, so the next read reopens the video.
  auto fail_and_close = [&](const std::string& problem) {
    open_.erase(path.string());
    fail(path, what + " " + problem);
  };

  if (frame < d.next || frame > d.next + kMaxForwardDecode) {
    if (!d.capture.set(cv::CAP_PROP_POS_FRAMES, frame)) fail_and_close("cannot be reached (seek failed)");
    d.next = frame;
  }
  for (; d.next < frame; ++d.next) {
    if (!d.capture.grab()) fail_and_close("cannot be decoded (the video ends or is corrupt before it)");
  }
  cv::Mat bgr;
  if (!d.capture.read(bgr) || bgr.empty()) fail_and_close("cannot be decoded (past the end of the video, or corrupt)");
  ++d.next;
  if (bgr.type() != CV_8UC3) fail_and_close("decodes to an unsupported pixel format (expected 8-bit BGR)");

  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::Mat values;
  rgb.convertTo(values, CV_32FC3, 1.0 / 255.0);  // a new, continuous matrix
  io::ImageF image{values.cols, values.rows, 3, {}};
  image.data.resize(values.total() * 3);
  std::memcpy(image.data.data(), values.ptr<float>(), image.data.size() * sizeof(float));
  return image;
}

}  // namespace s4d::data::detail
