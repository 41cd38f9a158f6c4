// libs4d_video.so: videos decoded and encoded by OpenCV's FFmpeg backend, behind video_plugin.h.
// The FFmpeg backend is named: left to choose, OpenCV also tries GStreamer, which prints warnings
// for every file it cannot open.
#include <memory>
#include <opencv2/videoio.hpp>

#include "video_plugin.h"

namespace s4d::data::video_plugin {

namespace {

class OpenCvCapture final : public Capture {
 public:
  explicit OpenCvCapture(const char* path) : capture_(path, cv::CAP_FFMPEG) {}
  bool opened() const { return capture_.isOpened(); }
  double width() const override { return capture_.get(cv::CAP_PROP_FRAME_WIDTH); }
  double height() const override { return capture_.get(cv::CAP_PROP_FRAME_HEIGHT); }
  double frame_count() const override { return capture_.get(cv::CAP_PROP_FRAME_COUNT); }
  bool read(cv::Mat& bgr) override { return capture_.read(bgr); }
  bool grab() override { return capture_.grab(); }
  bool seek(int frame) override { return capture_.set(cv::CAP_PROP_POS_FRAMES, frame); }

 private:
  cv::VideoCapture capture_;
};

class OpenCvEncoder final : public Encoder {
 public:
  OpenCvEncoder(const char* path, double fps, int width, int height)
      : writer_(path, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps, cv::Size(width, height)) {}
  bool opened() const { return writer_.isOpened(); }
  void write(const cv::Mat& bgr) override { writer_.write(bgr); }

 private:
  cv::VideoWriter writer_;
};

// An opened object, or nullptr.
template <class T, class... A>
T* opened_or_null(A... args) {
  auto object = std::make_unique<T>(args...);
  return object->opened() ? object.release() : nullptr;
}

const Api kApi = {
    kAbiVersion,
    [](const char* path) -> Capture* { return opened_or_null<OpenCvCapture>(path); },
    [](const char* path, double fps, int width, int height) -> Encoder* {
      return opened_or_null<OpenCvEncoder>(path, fps, width, height);
    },
};

}  // namespace

}  // namespace s4d::data::video_plugin

const s4d::data::video_plugin::Api* s4d_video_plugin_api() {
  return &s4d::data::video_plugin::kApi;
}
