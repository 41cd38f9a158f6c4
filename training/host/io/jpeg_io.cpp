// JPEG decoding through libjpeg(-turbo), in memory. libjpeg reports errors through error_exit,
// which must not return: it longjmps back to decode_jpeg's setjmp, which therefore holds only
// trivial locals (every container belongs to read_jpeg).
#include <csetjmp>
#include <cstdio>  // before jpeglib.h, which uses FILE
#include <string>
#include <vector>

#include <jpeglib.h>

#include "file_read.h"
#include "s4d/io/image_io.h"

namespace s4d::io {
namespace {

struct JpegError {
  jpeg_error_mgr manager;  // first, so libjpeg's pointer to it is a pointer to the whole
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void on_jpeg_error(j_common_ptr info) {
  auto* err = reinterpret_cast<JpegError*>(info->err);
  (*info->err->format_message)(info, err->message);
  std::longjmp(err->jump, 1);
}

// Warnings (a premature end of data, say) leave a usable, partly grey image, as other readers do.
void on_jpeg_warning(j_common_ptr, int) {}

// A header may claim any size: checked before allocating, as read_png does.
constexpr unsigned long long kMaxPixels = 1ull << 28;

// Decodes into `pixels` (8-bit RGB). Returns false with the message in `err` when libjpeg fails,
// or with `too_large` set when the header claims more than kMaxPixels.
bool decode_jpeg(const std::string& bytes, JpegError* err, jpeg_decompress_struct* info, std::vector<unsigned char>& pixels,
                 bool* too_large) {
  if (setjmp(err->jump)) return false;
  jpeg_mem_src(info, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(info, TRUE);
  info->out_color_space = JCS_RGB;  // grey and YCbCr alike; CMYK fails here, naming the conversion
  jpeg_start_decompress(info);
  *too_large = 1ull * info->output_width * info->output_height > kMaxPixels;
  if (*too_large) return false;
  pixels.resize(size_t{info->output_width} * info->output_height * 3);
  while (info->output_scanline < info->output_height) {
    JSAMPROW row = pixels.data() + size_t{info->output_scanline} * info->output_width * 3;
    jpeg_read_scanlines(info, &row, 1);
  }
  jpeg_finish_decompress(info);
  return true;
}

}  // namespace

ImageF read_jpeg(const std::filesystem::path& path) {
  const std::string bytes = detail::read_whole_file(path);
  JpegError err{};
  jpeg_decompress_struct info{};
  info.err = jpeg_std_error(&err.manager);
  err.manager.error_exit = on_jpeg_error;
  err.manager.emit_message = on_jpeg_warning;
  jpeg_create_decompress(&info);
  std::vector<unsigned char> pixels;
  bool too_large = false;
  const bool ok = decode_jpeg(bytes, &err, &info, pixels, &too_large);
  const int width = static_cast<int>(info.output_width), height = static_cast<int>(info.output_height);
  jpeg_destroy_decompress(&info);
  if (too_large) detail::fail(path, std::to_string(width) + "x" + std::to_string(height) + " is over the limit of " + std::to_string(kMaxPixels) + " pixels");
  if (!ok) detail::fail(path, std::string("corrupt JPEG: ") + err.message);
  ImageF image{width, height, 3, std::vector<float>(pixels.size())};
  for (size_t i = 0; i < pixels.size(); ++i) image.data[i] = static_cast<float>(pixels[i]) / 255.0f;
  return image;
}

}  // namespace s4d::io
