// A trained HexPlane carried over to another box or resolution: each texel of the new planes takes
// the old planes' bilinear value (align_corners = True, border clamp: the kernels' lookup,
// s4d_deform.h) at the point of space and time that texel stands for. Where the new texels include
// every old one and halve or evenly divide the cells between them, the new field equals the old one
// everywhere inside the new box; otherwise it equals it at the new texels and is their bilinear
// blend between them. Used to refit a field to the region that moves (train/field_box.h); the
// planes' Adam moments are carried over the same way.
#pragma once
#include <span>
#include <vector>

#include "s4d/deform/field_config.h"

namespace s4d::deform {

// `planes` laid out for `from` (deform_planes_total floats) as laid out for `to`. The two must agree
// on the number of levels and channels; std::invalid_argument naming the field otherwise, or when
// `planes` has the wrong size.
std::vector<float> resample_planes(const FieldConfig& from, const FieldConfig& to, std::span<const float> planes);

}  // namespace s4d::deform
