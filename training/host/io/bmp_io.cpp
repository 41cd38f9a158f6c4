// Uncompressed 24- and 32-bit BMP, the form image-quality data sets (KADID-10k, say) ship their
// pictures in; other BMP forms are refused by name.
#include <cstdint>
#include <string>

#include "file_read.h"
#include "s4d/io/image_io.h"

namespace s4d::io {
namespace {

uint32_t u32(const std::string& b, size_t at) {
  return static_cast<uint32_t>(static_cast<unsigned char>(b[at])) | static_cast<uint32_t>(static_cast<unsigned char>(b[at + 1])) << 8 |
         static_cast<uint32_t>(static_cast<unsigned char>(b[at + 2])) << 16 | static_cast<uint32_t>(static_cast<unsigned char>(b[at + 3])) << 24;
}
uint16_t u16(const std::string& b, size_t at) {
  return static_cast<uint16_t>(static_cast<unsigned char>(b[at]) | static_cast<unsigned char>(b[at + 1]) << 8);
}

}  // namespace

ImageF read_bmp(const std::filesystem::path& path) {
  const std::string b = detail::read_whole_file(path);
  if (b.size() < 54 || b[0] != 'B' || b[1] != 'M') detail::fail(path, "not a BMP file (bad signature or header)");
  const uint32_t offset = u32(b, 10);
  const int32_t width = static_cast<int32_t>(u32(b, 18)), signed_height = static_cast<int32_t>(u32(b, 22));
  const uint16_t bits = u16(b, 28);
  const uint32_t compression = u32(b, 30);
  if (compression != 0 || (bits != 24 && bits != 32))
    detail::fail(path, "BMP with " + std::to_string(bits) + " bits per pixel, compression " + std::to_string(compression) +
                           ": only uncompressed 24- and 32-bit BMP is read");
  // A negative height stores the rows top-down; positive, bottom-up.
  const int64_t height = signed_height < 0 ? -int64_t{signed_height} : signed_height;
  if (width <= 0 || height <= 0 || int64_t{width} * height > (int64_t{1} << 28))
    detail::fail(path, "BMP header: size " + std::to_string(width) + "x" + std::to_string(height) + " is empty or over 2^28 pixels");
  const size_t bytes_per_pixel = bits / 8, stride = (size_t{static_cast<uint32_t>(width)} * bytes_per_pixel + 3) / 4 * 4;
  if (b.size() < offset + stride * static_cast<size_t>(height)) detail::fail(path, "BMP is truncated (pixel rows missing)");
  ImageF image{width, static_cast<int>(height), 3, std::vector<float>(static_cast<size_t>(width) * static_cast<size_t>(height) * 3)};
  for (int64_t y = 0; y < height; ++y) {
    const size_t row = offset + stride * static_cast<size_t>(signed_height < 0 ? y : height - 1 - y);
    for (int32_t x = 0; x < width; ++x) {
      const size_t at = row + static_cast<size_t>(x) * bytes_per_pixel;
      float* out = image.data.data() + (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3;
      for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(static_cast<unsigned char>(b[at + 2 - static_cast<size_t>(c)])) / 255.0f;  // BGR
    }
  }
  return image;
}

}  // namespace s4d::io
