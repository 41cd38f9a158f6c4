// The layout of a row of DyNeRF / LLFF poses_bounds.npy ([N, 17] float64, one row per camera): the
// 3x5 matrix [c2w rotation | centre | hwf] flattened row-major (15 values), then the near and far
// bounds. hwf is the matrix's column 4: image height, width and focal length in pixels, at row-major
// indices 4, 9 and 14.
#pragma once
#include <cstddef>

namespace s4d::data {

inline constexpr size_t kPosesBoundsRow = 17;     // values per camera
inline constexpr size_t kPosesBoundsHeight = 4;   // hwf: H (row 0, column 4)
inline constexpr size_t kPosesBoundsWidth = 9;    // hwf: W (row 1, column 4)
inline constexpr size_t kPosesBoundsFocal = 14;   // hwf: focal (row 2, column 4)

}  // namespace s4d::data
