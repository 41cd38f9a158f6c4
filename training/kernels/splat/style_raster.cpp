#include "style_raster.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace s4d::splat {

static_assert(static_cast<uint32_t>(StyleDepth::ndc) == S4D_STYLE_DEPTH_NDC);
static_assert(static_cast<uint32_t>(StyleDepth::relative) == S4D_STYLE_DEPTH_RELATIVE);

void check_style(const StyleMlp& style) {
  if (style.depth != StyleDepth::ndc && style.depth != StyleDepth::relative)
    throw std::invalid_argument("rasterizer: unknown style depth mode " +
                                std::to_string(static_cast<uint32_t>(style.depth)));
  if (!std::isfinite(style.time) || !std::isfinite(style.depth_scale))
    throw std::invalid_argument("rasterizer: style time and depth_scale must be finite");
}

bool same_style_settings(const StyleMlp& a, const StyleMlp& b) {
  return a.time == b.time && a.depth == b.depth && a.depth_scale == b.depth_scale &&
         a.input_sigmoid == b.input_sigmoid;
}

gpu::RasterParams raster_params(const StyleMlp* style, const gpu::SplatCamera& cam,
                                const std::array<float, 3>& background, uint32_t flags) {
  gpu::RasterParams p{};
  p.size = cam.size;
  p.background = {background[0], background[1], background[2], 0.0f};
  p.flags = flags;
  if (style == nullptr) return p;
  p.intrinsics = cam.intrinsics;
  p.flags |= style->input_sigmoid ? S4D_STYLE_INPUT_SIGMOID : 0u;
  p.depth_mode = static_cast<uint32_t>(style->depth);
  p.time = style->time;
  p.depth_scale = style->depth_scale;
  return p;
}

}  // namespace s4d::splat
