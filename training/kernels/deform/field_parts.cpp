#include "s4d/deform/field_parts.h"

namespace s4d::deform {

namespace {

constexpr const char* kAxes = "xyzt";
constexpr const char* kHeads[S4D_DEFORM_HEADS] = {"pos", "scales", "rotations", "opacity", "sh"};

std::string linear_part(uint64_t index, uint32_t in, uint32_t out) {
  return index < uint64_t(in) * out ? "weight" : "bias";
}

}  // namespace

std::string plane_part(const gpu::DeformShape& s, uint64_t index) {
  for (uint32_t level = 0; level < s.levels; ++level)
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      const uint64_t begin = gpu::deform_plane_offset(s, level, p);
      if (index < begin + gpu::deform_plane_floats(s, level, p))
        return "level " + std::to_string(level) + " plane " + kAxes[S4D_DEFORM_PLANE_AXIS_U(p)] +
               kAxes[S4D_DEFORM_PLANE_AXIS_V(p)];
    }
  return "past the planes";
}

std::string mlp_part(const gpu::DeformShape& s, uint64_t index) {
  const uint32_t layers = gpu::deform_layer_count(s);
  for (uint32_t l = 0; l < layers; ++l) {
    const uint64_t begin = gpu::deform_layer_offset(s, l);
    const uint32_t in = gpu::deform_layer_in(s, l), out = gpu::deform_layer_out(s, l);
    if (index < begin || index >= begin + gpu::deform_linear_floats(in, out)) continue;
    const std::string what = linear_part(index - begin, in, out);
    if (l <= s.trunk_extra) return "trunk layer " + std::to_string(l) + " " + what;
    return std::string("head ") + kHeads[gpu::deform_layer_head(s, l)] +
           (gpu::deform_layer_is_head_out(s, l) ? " output " : " hidden ") + what;
  }
  return "past the MLP";
}

}  // namespace s4d::deform
