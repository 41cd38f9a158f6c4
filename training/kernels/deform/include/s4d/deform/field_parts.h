// Names of the parts of the deformation field's two parameter buffers (offsets: s4d_deform.h), so
// that a message can say which tensor holds a bad value: "level 1 plane xt", "head scales output bias".
#pragma once
#include <cstdint>
#include <string>

#include "s4d_deform.h"

namespace s4d::deform {

// The plane holding float `index` of the plane buffer ("level L plane UV"); "past the planes" beyond them.
std::string plane_part(const gpu::DeformShape& s, uint64_t index);
// The Linear layer and weight or bias holding float `index` of the MLP buffer ("trunk layer 0
// weight", "head pos hidden bias", "head sh output weight"); "past the MLP" beyond it.
std::string mlp_part(const gpu::DeformShape& s, uint64_t index);

}  // namespace s4d::deform
