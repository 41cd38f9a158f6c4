// Reading style and content pictures (PNG, JPEG, BMP) as RGB, and resizing.
#pragma once
#include <filesystem>

#include "s4d/io/image_io.h"

namespace s4d::io {

// RGB [H, W, 3] in [0, 1] (gray is replicated, alpha dropped, 16-bit scaled by 1/65535), the format
// found from the file's first bytes. Throws std::runtime_error naming the file when it is missing,
// of another format (TIFF, WebP, ...) or corrupt.
ImageF read_image_rgb(const std::filesystem::path& path);

// Area-averaging when shrinking, bilinear when enlarging. Throws std::invalid_argument for an empty
// image or a non-positive size.
ImageF resize_image(const ImageF& image, int width, int height);

}  // namespace s4d::io
