#include "s4d/data/video_writer.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "dataset_parts.h"
#include "video_plugin/video_plugin.h"

namespace s4d::data {

struct VideoWriter::Encoder {
  std::unique_ptr<video_plugin::Encoder> writer;
};

VideoWriter::VideoWriter(const std::filesystem::path& path, int width, int height, double fps)
    : path_(path), width_(width), height_(height) {
  if (width < 2 || height < 2 || width % 2 != 0 || height % 2 != 0) {
    throw std::invalid_argument(path.string() + ": video size must be even on both sides (mp4v stores chroma at half "
                                "resolution), got " + std::to_string(width) + "x" + std::to_string(height));
  }
  if (!(fps > 0)) throw std::invalid_argument(path.string() + ": fps must be positive");
  const std::string name = path.string();
  video_plugin::Encoder* writer = video_plugin::api(name.c_str()).open_encoder(name.c_str(), fps, width, height);
  encoder_ = std::make_unique<Encoder>(Encoder{std::unique_ptr<video_plugin::Encoder>(writer)});
  if (!encoder_->writer) {
    detail::fail(path, std::string("cannot open an ") + (path.extension() == ".webm" ? "VP9 (WebM)" : "mp4v (MPEG-4 Part 2)") + " encoder through OpenCV's FFmpeg backend: OpenCV is "
                       "built without FFmpeg or the encoder, or the file cannot be written");
  }
}

VideoWriter::~VideoWriter() = default;

void VideoWriter::write(const io::ImageF& rgb) {
  if (rgb.width != width_ || rgb.height != height_ || rgb.channels != 3 ||
      rgb.data.size() != static_cast<size_t>(width_) * static_cast<size_t>(height_) * 3) {
    throw std::invalid_argument(path_.string() + ": frame is " + std::to_string(rgb.width) + "x" +
                                std::to_string(rgb.height) + "x" + std::to_string(rgb.channels) + " (" + std::to_string(rgb.data.size()) + " values) but the video is " +
                                std::to_string(width_) + "x" + std::to_string(height_) + "x3");
  }
  // Clamp first: convertTo saturates, but NaN would not become 0 as it does in write_png.
  cv::Mat values(height_, width_, CV_32FC3);
  const float* src = rgb.data.data();
  float* dst = values.ptr<float>();
  for (size_t i = 0; i < rgb.data.size(); ++i) dst[i] = src[i] >= 0.0f ? (src[i] <= 1.0f ? src[i] : 1.0f) : 0.0f;
  cv::Mat levels, bgr;
  values.convertTo(levels, CV_8UC3, 255.0);  // rounds to nearest
  cv::cvtColor(levels, bgr, cv::COLOR_RGB2BGR);
  encoder_->writer->write(bgr);
}

}  // namespace s4d::data
