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

// Gray replicated, alpha dropped (read_png keeps a PNG's own channels).
ImageF rgb_of(ImageF image) {
  if (image.channels == 3) return image;
  ImageF rgb{image.width, image.height, 3, {}};
  const size_t pixels = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  const size_t c = static_cast<size_t>(image.channels);
  rgb.data.resize(pixels * 3);
  for (size_t i = 0; i < pixels; ++i)
    for (size_t k = 0; k < 3; ++k) rgb.data[3 * i + k] = image.data[i * c + (c < 3 ? 0 : k)];
  return rgb;
}

}  // namespace

ImageF read_image_rgb(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path.string() + ": no such file");
  // PNGs go through the project's reader: it names what is wrong with a damaged file, checks the
  // memory a huge one needs before decoding it, and keeps libpng's own lines off stderr.
  std::string head(8, '\0');
  std::ifstream(path, std::ios::binary).read(head.data(), 8);
  if (head == "\x89PNG\r\n\x1a\n") return rgb_of(read_png(path));
  const cv::Mat raw = cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (raw.empty()) throw std::runtime_error(path.string() + ": not a readable image (PNG, JPEG, ...)");
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
