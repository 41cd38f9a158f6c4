// libs4d_video.so: videos decoded and encoded by OpenCV's FFmpeg backend, behind video_plugin.h.
// The FFmpeg backend is named: left to choose, OpenCV also tries GStreamer, which prints warnings
// for every file it cannot open.
#include <memory>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/videoio.hpp>
#include <string>

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

bool is_webm(const std::string& path) { return path.size() >= 5 && path.compare(path.size() - 5, 5, ".webm") == 0; }

// VP9 in WebM for browsers (they do not play mp4v); mp4v in MP4 otherwise.
class OpenCvEncoder final : public Encoder {
 public:
  OpenCvEncoder(const char* path, double fps, int width, int height) {
    const bool webm = is_webm(path);
    const int fourcc = webm ? cv::VideoWriter::fourcc('V', 'P', '9', '0') : cv::VideoWriter::fourcc('m', 'p', '4', 'v');
    // WebM stores no codec tags, so OpenCV warns that 'VP90' is "not supported" and then encodes VP9
    // by the tag's codec id anyway: that warning is silenced, errors are not.
    const cv::utils::logging::LogLevel level = cv::utils::logging::getLogLevel();
    if (webm) cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    writer_.open(path, cv::CAP_FFMPEG, fourcc, fps, cv::Size(width, height));
    cv::utils::logging::setLogLevel(level);
  }
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
