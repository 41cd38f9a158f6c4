// Image files: PNG (8/16-bit, for renders and inputs), OpenEXR (32-bit float channels, for depth
// and other exact outputs), and JPEG and BMP read for style and content pictures. Writers replace
// their target atomically.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace s4d::io {

struct ImageF {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data;  // [H, W, C] row-major
};

// Writes a PNG with 1 (gray), 2 (gray + alpha), 3 (RGB) or 4 (RGBA) channels. Values are clamped
// to [0, 1] (NaN becomes 0) and rounded to the nearest level (v * 255 + 0.5, or 65535 with
// bit_depth 16); no gamma conversion. Throws std::invalid_argument for a bad shape or bit depth,
// std::runtime_error naming the file when encoding or writing fails.
void write_png(const std::filesystem::path& path, const ImageF& image, int bit_depth = 8);

// Reads any PNG: 1-16 bit gray, gray + alpha, RGB, RGBA or palette (expanded to RGB, or RGBA
// when it has transparency). Values are level / 255 or level / 65535 (16-bit), no gamma
// conversion. Throws std::runtime_error naming the file when it is missing, not a PNG, truncated
// or corrupt.
ImageF read_png(const std::filesystem::path& path);

// Reads a JPEG (grey or colour; CMYK is refused) as 8-bit RGB, values level / 255. Throws
// std::runtime_error naming the file when it is missing, not a JPEG, truncated or corrupt.
ImageF read_jpeg(const std::filesystem::path& path);

// Reads an uncompressed 24- or 32-bit BMP as RGB (a 32-bit one's fourth byte dropped), values
// level / 255. Throws std::runtime_error naming the file for any other BMP or a damaged one.
ImageF read_bmp(const std::filesystem::path& path);

// Writes a scanline OpenEXR with one 32-bit FLOAT channel per entry (e.g. "R", "G", "B", "A",
// "Z"), each pointing at width * height values in row-major order, ZIP compression. Throws
// std::invalid_argument for bad sizes, empty, null or duplicate channels; std::runtime_error
// naming the file when writing fails.
void write_exr(const std::filesystem::path& path, int width, int height,
               const std::vector<std::pair<std::string, const float*>>& channels);

struct ExrImage {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> channels;  // each [H, W] row-major
};

// Reads every channel of an OpenEXR (single-part, scanline or tiled) as float over its data
// window. Throws std::runtime_error naming the file on any failure.
ExrImage read_exr(const std::filesystem::path& path);

}  // namespace s4d::io
