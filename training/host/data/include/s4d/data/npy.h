// NumPy .npy files holding one little-endian float32 or float64 array in C order (what
// poses_bounds.npy is), read into doubles. Format versions 1.0, 2.0 and 3.0.
#pragma once
#include <cstddef>
#include <filesystem>
#include <vector>

namespace s4d::data {

struct NpyArray {
  std::vector<size_t> shape;
  std::vector<double> values;  // row-major
};

// Throws std::runtime_error naming the file: not a .npy, unsupported dtype or byte order, Fortran
// order, or a truncated data section.
NpyArray read_npy(const std::filesystem::path& path);

// Writes float64, format 1.0, atomically.
void write_npy(const std::filesystem::path& path, const NpyArray& array);

}  // namespace s4d::data
