// Host side of the rasterizer family's style variants (GaussianParams::style): argument checks, and
// the push constants of both variants. Private to s4d_splat; the Rasterizer records the dispatches.
#pragma once
#include <array>
#include <cstdint>

#include "s4d/splat/rasterizer.h"
#include "s4d_style_splat.h"

namespace s4d::splat {

// Throws std::invalid_argument naming the field when `style`'s settings are invalid (the weights
// are GaussianParams[Attr::style_mlp], checked with the other attributes).
void check_style(const StyleMlp& style);

// Whether two descriptions render the same.
bool same_style_settings(const StyleMlp& a, const StyleMlp& b);

// Push constants of raster_fwd / raster_bwd, plain (style == nullptr) or style variant; `flags`
// holds S4D_RASTER_HAS_V_* bits.
gpu::RasterParams raster_params(const StyleMlp* style, const gpu::SplatCamera& cam,
                                const std::array<float, 3>& background, uint32_t flags);

}  // namespace s4d::splat
