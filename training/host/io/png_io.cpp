// PNG encode/decode through libpng's classic API, entirely in memory: the file is read whole
// (errors name it and say why) and written through the atomic replace.
//
// libpng reports errors by calling on_png_error, which must not return: it longjmps back to the
// setjmp of the function that made the failing call. A longjmp must not skip any C++ object with
// a destructor, so the functions that call setjmp (encode, decode_header, decode_rows) hold only
// trivial locals, every container belongs to their callers, and the callbacks never let a C++
// exception unwind through libpng.
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "file_read.h"
#include "s4d/io/image_io.h"
#include "s4d/util/atomic_file.h"
#include "s4d/util/free_memory.h"

namespace s4d::io {
namespace {

struct PngError {
  char message[256] = {};
};

[[noreturn]] void on_png_error(png_structp png, png_const_charp msg) {
  auto* err = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(err->message, sizeof(err->message), "%s", msg);
  png_longjmp(png, 1);
}

// Warnings (an odd iCCP profile, say) do not make an image unusable.
void on_png_warning(png_structp, png_const_charp) {}

// ---- writing ----

void on_png_write(png_structp png, png_bytep data, size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  bool ok = true;
  try {
    out->append(reinterpret_cast<const char*>(data), length);
  } catch (const std::bad_alloc&) {
    ok = false;
  }
  if (!ok) png_error(png, "out of memory");  // outside the catch: it longjmps
}

void on_png_flush(png_structp) {}

class PngWriteStruct {
 public:
  explicit PngWriteStruct(PngError* err)
      : png_(png_create_write_struct(PNG_LIBPNG_VER_STRING, err, on_png_error, on_png_warning)) {
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) {
      png_destroy_write_struct(&png_, &info_);
      throw std::bad_alloc();
    }
  }
  ~PngWriteStruct() { png_destroy_write_struct(&png_, &info_); }
  PngWriteStruct(const PngWriteStruct&) = delete;
  PngWriteStruct& operator=(const PngWriteStruct&) = delete;

  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  png_structp png_;
  png_infop info_ = nullptr;
};

// Returns false (with the message in the error state) when libpng fails.
bool encode(png_structp png, png_infop info, png_uint_32 width, png_uint_32 height, int bit_depth, int color_type,
            png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

int color_type_for(int channels) {
  switch (channels) {
    case 1:
      return PNG_COLOR_TYPE_GRAY;
    case 2:
      return PNG_COLOR_TYPE_GRAY_ALPHA;
    case 3:
      return PNG_COLOR_TYPE_RGB;
    default:
      return PNG_COLOR_TYPE_RGB_ALPHA;
  }
}

// Clamped, NaN-safe, round-to-nearest quantisation to [0, max_level].
unsigned quantise(float v, double max_level) {
  const double clamped = std::isnan(v) ? 0.0 : std::clamp(static_cast<double>(v), 0.0, 1.0);
  return static_cast<unsigned>(clamped * max_level + 0.5);
}

// ---- reading ----

struct PngInput {
  const unsigned char* data;
  size_t size;
  size_t pos;
};

void on_png_read(png_structp png, png_bytep out, size_t length) {
  auto* in = static_cast<PngInput*>(png_get_io_ptr(png));
  if (length > in->size - in->pos) png_error(png, "truncated (unexpected end of data)");
  std::memcpy(out, in->data + in->pos, length);
  in->pos += length;
}

class PngReadStruct {
 public:
  explicit PngReadStruct(PngError* err)
      : png_(png_create_read_struct(PNG_LIBPNG_VER_STRING, err, on_png_error, on_png_warning)) {
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) {
      png_destroy_read_struct(&png_, &info_, nullptr);
      throw std::bad_alloc();
    }
  }
  ~PngReadStruct() { png_destroy_read_struct(&png_, &info_, nullptr); }
  PngReadStruct(const PngReadStruct&) = delete;
  PngReadStruct& operator=(const PngReadStruct&) = delete;

  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  png_structp png_;
  png_infop info_ = nullptr;
};

struct PngShape {
  png_uint_32 width, height;
  int channels, bit_depth;
  size_t row_bytes;
};

bool decode_header(png_structp png, png_infop info, PngShape* shape) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  // Palette -> RGB (RGBA with tRNS), gray below 8 bits -> 8 bits, tRNS -> alpha channel.
  png_set_expand(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  shape->width = png_get_image_width(png, info);
  shape->height = png_get_image_height(png, info);
  shape->channels = png_get_channels(png, info);
  shape->bit_depth = png_get_bit_depth(png, info);
  shape->row_bytes = png_get_rowbytes(png, info);
  return true;
}

bool decode_rows(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);  // reads to IEND, so a file cut after the pixels is still caught
  return true;
}

}  // namespace

void write_png(const std::filesystem::path& path, const ImageF& image, int bit_depth) {
  if (bit_depth != 8 && bit_depth != 16) {
    throw std::invalid_argument("write_png: bit_depth must be 8 or 16, got " + std::to_string(bit_depth));
  }
  if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 4) {
    throw std::invalid_argument("write_png: bad shape " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + "x" + std::to_string(image.channels) +
                                " (need positive sizes and 1 to 4 channels)");
  }
  const size_t w = static_cast<size_t>(image.width);
  const size_t h = static_cast<size_t>(image.height);
  const size_t c = static_cast<size_t>(image.channels);
  if (image.data.size() != w * h * c) {
    throw std::invalid_argument("write_png: data has " + std::to_string(image.data.size()) + " values; expected " +
                                std::to_string(w * h * c));
  }
  const size_t bytes_per_value = bit_depth == 16 ? 2 : 1;
  const double max_level = bit_depth == 16 ? 65535.0 : 255.0;
  std::vector<png_byte> pixels(w * h * c * bytes_per_value);
  for (size_t i = 0; i < w * h * c; ++i) {
    const unsigned level = quantise(image.data[i], max_level);
    if (bit_depth == 16) {
      pixels[2 * i] = static_cast<png_byte>(level >> 8);  // PNG samples are big-endian
      pixels[2 * i + 1] = static_cast<png_byte>(level & 0xff);
    } else {
      pixels[i] = static_cast<png_byte>(level);
    }
  }
  std::vector<png_bytep> rows(h);
  for (size_t y = 0; y < h; ++y) rows[y] = pixels.data() + y * w * c * bytes_per_value;

  PngError err;
  std::string bytes;
  const PngWriteStruct s(&err);
  png_set_write_fn(s.png(), &bytes, on_png_write, on_png_flush);
  if (!encode(s.png(), s.info(), static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), bit_depth,
              color_type_for(image.channels), rows.data())) {
    detail::fail(path, std::string("cannot encode PNG: ") + err.message);
  }
  util::write_file_atomic(path, bytes);
}

ImageF read_png(const std::filesystem::path& path) {
  const std::string bytes = detail::read_whole_file(path);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 8 || png_sig_cmp(data, 0, 8) != 0) detail::fail(path, "not a PNG file (bad signature)");

  PngError err;
  PngInput input{data, bytes.size(), 0};
  const PngReadStruct s(&err);
  png_set_read_fn(s.png(), &input, on_png_read);
  PngShape shape{};
  if (!decode_header(s.png(), s.info(), &shape)) detail::fail(path, std::string("corrupt PNG: ") + err.message);
  // Checked before allocating: a header may claim any size (a decompression bomb, or a damaged file).
  constexpr uint64_t kMaxPixels = uint64_t{1} << 28;  // 268 M pixels: 16384 x 16384, 4 GiB as floats x4
  if (uint64_t{shape.width} * shape.height > kMaxPixels) {
    detail::fail(path, "IHDR: " + std::to_string(shape.width) + "x" + std::to_string(shape.height) +
                           " is over the limit of " + std::to_string(kMaxPixels) + " pixels");
  }
  // The decoded rows, their floats and the RGB copy most callers make: asked for before any of it.
  const uint64_t pixels_count = uint64_t{shape.width} * shape.height;
  util::require_memory(path.string(), shape.row_bytes * uint64_t{shape.height} + pixels_count * (shape.channels + 3) * 4,
                       "decoding its " + std::to_string(shape.width) + "x" + std::to_string(shape.height) + " pixels");

  std::vector<png_byte> pixels(shape.row_bytes * shape.height);
  std::vector<png_bytep> rows(shape.height);
  for (size_t y = 0; y < shape.height; ++y) rows[y] = pixels.data() + y * shape.row_bytes;
  if (!decode_rows(s.png(), s.info(), rows.data())) detail::fail(path, std::string("corrupt PNG: ") + err.message);

  ImageF image;
  image.width = static_cast<int>(shape.width);
  image.height = static_cast<int>(shape.height);
  image.channels = shape.channels;
  const size_t values_per_row = static_cast<size_t>(shape.width) * static_cast<size_t>(shape.channels);
  image.data.resize(values_per_row * shape.height);
  for (size_t y = 0; y < shape.height; ++y) {
    const png_byte* row = rows[y];
    float* out = image.data.data() + y * values_per_row;
    for (size_t i = 0; i < values_per_row; ++i) {
      out[i] = shape.bit_depth == 16 ? static_cast<float>((row[2 * i] << 8) | row[2 * i + 1]) / 65535.0f
                                     : static_cast<float>(row[i]) / 255.0f;
    }
  }
  return image;
}

}  // namespace s4d::io
