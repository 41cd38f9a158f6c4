#include "s4d/io/image_file.h"

#include <fstream>
#include <stdexcept>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "s4d/io/image_io.h"

namespace s4d::io {

namespace {

// An RGB image from a CV_32FC3 matrix that OpenCV has just made (so it is continuous).
ImageF image_from(const cv::Mat& rgb) {
  ImageF image{rgb.cols, rgb.rows, 3, {}};
  image.data.assign(rgb.ptr<float>(), rgb.ptr<float>() + rgb.total() * 3);
  return image;
}

}  // namespace

ImageF read_image_rgb(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path.string() + ": no such file");
  const cv::Mat raw = cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (raw.empty()) {
    // OpenCV does not say why; the project's PNG reader names what is wrong with a PNG (and throws).
    std::string head(8, '\0');
    std::ifstream(path, std::ios::binary).read(head.data(), 8);
    if (head == "\x89PNG\r\n\x1a\n") (void)read_png(path);
    throw std::runtime_error(path.string() + ": not a readable image (PNG, JPEG, ...)");
  }
  cv::Mat rgb;
  switch (raw.channels()) {
    case 1: cv::cvtColor(raw, rgb, cv::COLOR_GRAY2RGB); break;
    case 3: cv::cvtColor(raw, rgb, cv::COLOR_BGR2RGB); break;
    case 4: cv::cvtColor(raw, rgb, cv::COLOR_BGRA2RGB); break;
    default: throw std::runtime_error(path.string() + ": " + std::to_string(raw.channels()) + " channels, expected 1, 3 or 4");
  }
  const double scale = rgb.depth() == CV_16U ? 1.0 / 65535 : rgb.depth() == CV_8U ? 1.0 / 255 : 1.0;
  cv::Mat f;
  rgb.convertTo(f, CV_32FC3, scale);
  return image_from(f);
}

ImageF resize_image(const ImageF& image, int width, int height) {
  if (image.width <= 0 || image.height <= 0 || image.channels != 3 || width <= 0 || height <= 0)
    throw std::invalid_argument("resize_image: needs a non-empty RGB image and a positive size");
  const cv::Mat in(image.height, image.width, CV_32FC3, const_cast<float*>(image.data.data()));  // read only
  cv::Mat out;
  const bool shrink = width < image.width || height < image.height;
  cv::resize(in, out, cv::Size(width, height), 0, 0, shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
  return image_from(out);
}

}  // namespace s4d::io
