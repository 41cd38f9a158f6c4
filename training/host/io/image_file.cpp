#include "s4d/io/image_file.h"

#include <fstream>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

#include "file_read.h"
#include "s4d/io/image_io.h"

namespace s4d::io {

namespace {

// An RGB image from a CV_32FC3 matrix that OpenCV has just made (so it is continuous).
ImageF image_from(const cv::Mat& rgb) {
  ImageF image{rgb.cols, rgb.rows, 3, {}};
  image.data.assign(rgb.ptr<float>(), rgb.ptr<float>() + rgb.total() * 3);
  return image;
}

// Gray replicated, alpha dropped.
ImageF to_rgb(const std::filesystem::path& path, ImageF image) {
  if (image.channels == 3) return image;
  if (image.channels < 1 || image.channels > 4) detail::fail(path, std::to_string(image.channels) + " channels, expected 1 to 4");
  const size_t pixels = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  const size_t in = static_cast<size_t>(image.channels);
  ImageF rgb{image.width, image.height, 3, std::vector<float>(pixels * 3)};
  for (size_t p = 0; p < pixels; ++p)
    for (size_t c = 0; c < 3; ++c) rgb.data[p * 3 + c] = image.data[p * in + (in >= 3 ? c : 0)];
  return rgb;
}

}  // namespace

// The format from the file's first bytes, not its name.
ImageF read_image_rgb(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path.string() + ": no such file");
  std::string head(8, '\0');
  std::ifstream(path, std::ios::binary).read(head.data(), 8);
  if (head == "\x89PNG\r\n\x1a\n") return to_rgb(path, read_png(path));
  if (head.starts_with("\xff\xd8\xff")) return read_jpeg(path);
  if (head.starts_with("BM")) return read_bmp(path);
  detail::fail(path, "not a readable image (PNG, JPEG or BMP)");
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
