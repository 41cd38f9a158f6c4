// 3D Gaussian Splatting PLY files, in the layout of the original implementation (Kerbl et al.
// 2023, graphdeco-inria/gaussian-splatting, GaussianModel.save_ply), which viewers and other
// trainers also read: binary_little_endian 1.0, one element 'vertex' with float properties
//   x y z  nx ny nz  f_dc_0..2  f_rest_0..(3*(K-1)-1)  opacity  scale_0..2  rot_0..3
// where opacity is a logit, scales are logs, rot is an unnormalised quaternion (w, x, y, z) and
// K = (degree+1)^2 spherical-harmonic coefficients per colour channel.
#pragma once
#include <cstddef>
#include <filesystem>
#include <vector>

namespace s4d::io {

struct GaussianCloud {
  std::vector<float> means;           // [N, 3]
  std::vector<float> log_scales;      // [N, 3]
  std::vector<float> quats;           // [N, 4] w, x, y, z; not normalised
  std::vector<float> opacity_logits;  // [N]
  // [N, K, 3] coefficient-major: sh[(i*K + k)*3 + ch]. Coefficient 0 is the DC term (f_dc).
  std::vector<float> sh;
  int sh_degree = 0;  // 0..3

  size_t size() const { return means.size() / 3; }
  size_t sh_coeffs() const { return static_cast<size_t>((sh_degree + 1) * (sh_degree + 1)); }
};

// Reads a 3DGS PLY. Properties may come in any order and as float or double; unknown extra
// properties, nx/ny/nz and other elements (before or after 'vertex', list properties included)
// are skipped. In the file, f_rest is channel-major: f_rest_j holds channel j/(K-1),
// coefficient 1 + j%(K-1). Throws std::runtime_error naming the file and the problem: not a PLY,
// ascii or big-endian format, a missing required property, an f_rest count other than 0, 9, 24
// or 45, a list property in 'vertex', truncated data, or a non-finite value (naming the vertex
// and property).
GaussianCloud read_ply_gaussians(const std::filesystem::path& path);

// Writes `cloud` in exactly the standard layout (nx, ny, nz = 0), replacing `path` atomically.
// Throws std::invalid_argument when the arrays do not match size() and sh_degree, or a value is
// not finite (the reader would reject the file); std::runtime_error when writing fails.
void write_ply_gaussians(const std::filesystem::path& path, const GaussianCloud& cloud);

}  // namespace s4d::io
