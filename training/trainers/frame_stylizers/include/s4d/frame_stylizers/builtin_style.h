// The built-in style image: a procedural, deterministic painting (brush strokes of a fixed palette
// over a canvas weave), so the product has a style without any external file. assets/styles/builtin.png
// is this function's output at the default size and seed (`style4d make-style` regenerates it).
#pragma once
#include <cstdint>

#include "s4d/io/image_io.h"

namespace s4d::frame_stylizers {

// RGB [size, size, 3] in [0, 1]. Throws std::invalid_argument for size < 32.
io::ImageF builtin_style(int size = 384, uint64_t seed = 0);

}  // namespace s4d::frame_stylizers
