// CPU twin of the 3DGS preprocess (ALGORITHMS.md 1.1-1.3, 1.6 "Preprocess backward"): per Gaussian,
// activations, covariance, EWA projection, conic, 3-sigma radius, 16x16 tile rectangle and SH colour,
// forward and backward. Templated on the scalar type (float, double). Plain sequential C++.
//
// Layout: SoA flat arrays, as on the GPU (STYLE.md 3.3). Pixel convention: pixel (i, j) has its centre
// at (i + 0.5, j + 0.5); u = fx*x/z + cx, v = fy*y/z + cy (ALGORITHMS.md 1.2 "This project's convention").
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "s4d/util/vec3.h"
#include "s4d_splat.h"

namespace s4d::ref {

// Rasterizer constants: the kernels' values from shaders/shared/s4d_splat.h.
inline constexpr int kTileSize = S4D_TILE_SIZE;
inline constexpr double kNearZ = S4D_NEAR_Z;
inline constexpr double kGuardBand = S4D_GUARD_BAND;
inline constexpr double kDilation = S4D_DILATION;
inline constexpr double kSigmaExtent = S4D_SIGMA_EXTENT;
inline constexpr double kMinEigenGap = S4D_MIN_EIGEN_GAP;
inline constexpr double kMaxAlpha = S4D_MAX_ALPHA;
inline constexpr double kMinAlpha = S4D_MIN_ALPHA;
inline constexpr double kMinTransmittance = S4D_MIN_TRANSMITTANCE;

inline constexpr int kMaxShDegree = S4D_MAX_SH_DEGREE;
inline constexpr double kShC0 = 0.28209479177387814;
inline constexpr double kShC1 = 0.4886025119029199;
inline constexpr std::array<double, 5> kShC2 = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
                                                -1.0925484305920792, 0.5462742152960396};
inline constexpr std::array<double, 7> kShC3 = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658,
                                                0.3731763325901154,  -0.4570457994644658, 1.445305721320277,
                                                -0.5900435899266435};

template <class T>
struct Gaussians {
  std::vector<T> means;           // [N, 3] world
  std::vector<T> log_scales;      // [N, 3] scale = exp(log_scale)
  std::vector<T> quats;           // [N, 4] (w, x, y, z), un-normalised; the twin normalises
  std::vector<T> opacity_logits;  // [N] opacity = sigmoid(logit)
  std::vector<T> sh;              // [N, K, 3] coefficient-major, K >= (sh_degree + 1)^2
  std::vector<T> colors;          // [N, 3] optional: when non-empty it replaces the SH colour
  int sh_degree = 0;              // active degree, 0..3

  size_t size() const { return opacity_logits.size(); }
  size_t sh_coeffs() const { return size() == 0 ? 0 : sh.size() / (3 * size()); }
};

template <class T>
struct Camera {
  std::array<T, 16> world_to_cam{};  // row-major 4x4, OpenCV axes (x right, y down, z forward)
  T fx{}, fy{}, cx{}, cy{};
  int width = 0, height = 0;

  int tiles_x() const { return (width + kTileSize - 1) / kTileSize; }
  int tiles_y() const { return (height + kTileSize - 1) / kTileSize; }
};

// Forward outputs of the preprocess, one entry per input Gaussian.
template <class T>
struct Projected {
  std::vector<T> mean2d;          // [N, 2] pixels
  std::vector<T> conic;           // [N, 3] (A, B, C): inverse of the dilated 2D covariance
  std::vector<T> depth;           // [N] camera-space z
  std::vector<T> opacity;         // [N] sigmoid(logit)
  std::vector<T> rgb;             // [N, 3]
  std::vector<int> radius;        // [N] pixels; 0 means culled
  std::vector<int> tile_rect;     // [N, 4] (x_min, y_min, x_max, y_max) in tiles, max exclusive
  std::vector<uint8_t> clamped;   // [N, 3] 1 where the SH colour was clamped at 0 (no gradient)
};

// Cotangents of the Projected quantities (what the raster backward produces).
template <class T>
struct ProjectedGrads {
  std::vector<T> v_mean2d;   // [N, 2] dL/d(u, v), pixel units
  std::vector<T> v_conic;    // [N, 3] dL/d(A, B, C); B is the scalar off-diagonal (full, not halved)
  std::vector<T> v_depth;    // [N]
  std::vector<T> v_opacity;  // [N] dL/d(sigmoid(logit))
  std::vector<T> v_rgb;      // [N, 3]

  ProjectedGrads() = default;
  explicit ProjectedGrads(size_t n) : v_mean2d(2 * n), v_conic(3 * n), v_depth(n), v_opacity(n), v_rgb(3 * n) {}
};

// Gradients with respect to the raw parameters.
template <class T>
struct GaussianGrads {
  std::vector<T> v_means, v_log_scales, v_quats, v_opacity_logits, v_sh, v_colors;
  std::vector<T> v_mean2d;  // [N, 2] dL/d(u, v) in pixels (graphdeco's NDC value is this times W/2, H/2)
};

namespace detail {

template <class T>
constexpr T lit(double v) { return static_cast<T>(v); }

template <class T>
using Mat3 = std::array<T, 9>;  // row-major

// Real spherical harmonics basis Y_k(d) and, when dY is non-null, dY_k/d(x, y, z) with x, y, z
// treated as independent (the projection onto the sphere's tangent is applied by the caller).
template <class T>
void sh_basis(int degree, const Vec3Of<T>& d, std::array<T, 16>& Y, std::array<Vec3Of<T>, 16>* dY) {
  const T x = d[0], y = d[1], z = d[2];
  const T c0 = lit<T>(kShC0), c1 = lit<T>(kShC1);
  auto c2 = [](int k) { return lit<T>(kShC2[static_cast<size_t>(k)]); };
  auto c3 = [](int k) { return lit<T>(kShC3[static_cast<size_t>(k)]); };
  const T xx = x * x, yy = y * y, zz = z * z;
  Y = {};
  Y[0] = c0;
  if (degree >= 1) {
    Y[1] = -c1 * y, Y[2] = c1 * z, Y[3] = -c1 * x;
  }
  if (degree >= 2) {
    Y[4] = c2(0) * x * y, Y[5] = c2(1) * y * z, Y[6] = c2(2) * (2 * zz - xx - yy);
    Y[7] = c2(3) * x * z, Y[8] = c2(4) * (xx - yy);
  }
  if (degree >= 3) {
    Y[9] = c3(0) * y * (3 * xx - yy), Y[10] = c3(1) * x * y * z, Y[11] = c3(2) * y * (4 * zz - xx - yy);
    Y[12] = c3(3) * z * (2 * zz - 3 * xx - 3 * yy), Y[13] = c3(4) * x * (4 * zz - xx - yy);
    Y[14] = c3(5) * z * (xx - yy), Y[15] = c3(6) * x * (xx - 3 * yy);
  }
  if (dY == nullptr) return;
  auto& g = *dY;
  g = {};
  if (degree >= 1) {
    g[1] = {T(0), -c1, T(0)}, g[2] = {T(0), T(0), c1}, g[3] = {-c1, T(0), T(0)};
  }
  if (degree >= 2) {
    g[4] = {c2(0) * y, c2(0) * x, T(0)};
    g[5] = {T(0), c2(1) * z, c2(1) * y};
    g[6] = {-2 * c2(2) * x, -2 * c2(2) * y, 4 * c2(2) * z};
    g[7] = {c2(3) * z, T(0), c2(3) * x};
    g[8] = {2 * c2(4) * x, -2 * c2(4) * y, T(0)};
  }
  if (degree >= 3) {
    g[9] = {c3(0) * 6 * x * y, c3(0) * (3 * xx - 3 * yy), T(0)};
    g[10] = {c3(1) * y * z, c3(1) * x * z, c3(1) * x * y};
    g[11] = {-2 * c3(2) * x * y, c3(2) * (4 * zz - xx - 3 * yy), 8 * c3(2) * y * z};
    g[12] = {-6 * c3(3) * x * z, -6 * c3(3) * y * z, c3(3) * (6 * zz - 3 * xx - 3 * yy)};
    g[13] = {c3(4) * (4 * zz - 3 * xx - yy), -2 * c3(4) * x * y, 8 * c3(4) * x * z};
    g[14] = {2 * c3(5) * x * z, -2 * c3(5) * y * z, c3(5) * (xx - yy)};
    g[15] = {c3(6) * (3 * xx - 3 * yy), -6 * c3(6) * x * y, T(0)};
  }
}

// Every intermediate of one Gaussian's preprocess; the backward recomputes it instead of storing it.
template <class T>
struct Projection {
  bool visible = false;
  std::array<T, 4> q{};  // normalised (w, x, y, z)
  T q_norm{};            // |raw quaternion|; 0 means "no rotation information", see normalise_quat
  Mat3<T> R{};           // world rotation of the Gaussian
  Vec3Of<T> s{};         // scales
  Mat3<T> sigma{};       // 3D covariance
  Mat3<T> W{};           // rotation part of world_to_cam
  Vec3Of<T> t{};         // camera-space mean
  T rx{}, ry{};          // x/z and y/z after the guard-band clamp
  bool clamp_x = false, clamp_y = false;
  std::array<T, 6> M{};  // J*W, 2x3 row-major
  T a{}, b{}, c{}, det{};  // dilated 2D covariance [[a, b], [b, c]]
  Vec3Of<T> dir{};       // normalize(mean - campos), for SH
  T dist{};              // |mean - campos|
};

// Normalises robustly: dividing by the largest component first keeps tiny quaternions (1e-20
// components) from underflowing in float. An all-zero or non-finite quaternion gives the identity
// rotation and q_norm = 0, which the backward reads as "no gradient".
template <class T>
void normalise_quat(const T* raw, std::array<T, 4>& q, T& norm) {
  T big = 0;
  for (int k = 0; k < 4; ++k) big = std::max(big, std::abs(raw[k]));
  if (!(big > 0) || !std::isfinite(big)) {
    q = {T(1), T(0), T(0), T(0)};
    norm = 0;
    return;
  }
  T sum = 0;
  for (int k = 0; k < 4; ++k) sum += (raw[k] / big) * (raw[k] / big);
  const T root = std::sqrt(sum);
  for (int k = 0; k < 4; ++k) q[static_cast<size_t>(k)] = (raw[k] / big) / root;
  norm = big * root;
}

template <class T>
Mat3<T> quat_to_rot(const std::array<T, 4>& q) {
  const T w = q[0], x = q[1], y = q[2], z = q[3];
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

template <class T>
Projection<T> project_one(const Gaussians<T>& g, size_t i, const Camera<T>& cam) {
  Projection<T> p;
  const auto& V = cam.world_to_cam;
  p.W = {V[0], V[1], V[2], V[4], V[5], V[6], V[8], V[9], V[10]};
  const T* mu = &g.means[3 * i];
  for (size_t r = 0; r < 3; ++r)
    p.t[r] = p.W[3 * r] * mu[0] + p.W[3 * r + 1] * mu[1] + p.W[3 * r + 2] * mu[2] + V[4 * r + 3];
  if (!(p.t[2] > lit<T>(kNearZ)) || std::isinf(p.t[2])) return p;
  if (std::isnan(g.quats[4 * i]) || std::isnan(g.quats[4 * i + 1]) || std::isnan(g.quats[4 * i + 2]) ||
      std::isnan(g.quats[4 * i + 3]))
    return p;  // culled, as on the GPU

  normalise_quat(&g.quats[4 * i], p.q, p.q_norm);
  p.R = quat_to_rot(p.q);
  for (size_t k = 0; k < 3; ++k) p.s[k] = std::exp(g.log_scales[3 * i + k]);
  for (size_t r = 0; r < 3; ++r)
    for (size_t c = 0; c < 3; ++c) {
      T acc = 0;
      for (size_t k = 0; k < 3; ++k) acc += p.R[3 * r + k] * p.s[k] * p.s[k] * p.R[3 * c + k];
      p.sigma[3 * r + c] = acc;
    }

  // EWA Jacobian with the guard band on x/z and y/z (1.3 step 3).
  const T tz = p.t[2];
  const T lim_x = lit<T>(kGuardBand) * static_cast<T>(cam.width) / (2 * cam.fx);
  const T lim_y = lit<T>(kGuardBand) * static_cast<T>(cam.height) / (2 * cam.fy);
  p.rx = p.t[0] / tz, p.ry = p.t[1] / tz;
  p.clamp_x = std::abs(p.rx) > lim_x, p.clamp_y = std::abs(p.ry) > lim_y;
  p.rx = std::clamp(p.rx, -lim_x, lim_x), p.ry = std::clamp(p.ry, -lim_y, lim_y);
  const std::array<T, 6> J = {cam.fx / tz, T(0), -cam.fx * p.rx / tz, T(0), cam.fy / tz, -cam.fy * p.ry / tz};
  for (size_t r = 0; r < 2; ++r)
    for (size_t c = 0; c < 3; ++c)
      p.M[3 * r + c] = J[3 * r] * p.W[c] + J[3 * r + 1] * p.W[3 + c] + J[3 * r + 2] * p.W[6 + c];

  // Sigma2D = M Sigma M^T, plus the low-pass dilation on the diagonal.
  auto quad = [&](size_t r0, size_t r1) {
    T acc = 0;
    for (size_t k = 0; k < 3; ++k)
      for (size_t l = 0; l < 3; ++l) acc += p.M[3 * r0 + k] * p.sigma[3 * k + l] * p.M[3 * r1 + l];
    return acc;
  };
  p.a = quad(0, 0) + lit<T>(kDilation), p.b = quad(0, 1), p.c = quad(1, 1) + lit<T>(kDilation);
  p.det = p.a * p.c - p.b * p.b;
  // graphdeco drops det == 0 only; a PSD covariance plus dilation has det > 0, so "not > 0" also
  // catches rounding and NaN.
  p.visible = p.det > 0;

  const Vec3Of<T> campos = {-(p.W[0] * V[3] + p.W[3] * V[7] + p.W[6] * V[11]),
                          -(p.W[1] * V[3] + p.W[4] * V[7] + p.W[7] * V[11]),
                          -(p.W[2] * V[3] + p.W[5] * V[7] + p.W[8] * V[11])};
  const Vec3Of<T> d = {mu[0] - campos[0], mu[1] - campos[1], mu[2] - campos[2]};
  p.dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (size_t k = 0; k < 3; ++k) p.dir[k] = d[k] / p.dist;
  return p;
}

}  // namespace detail

// Preprocess forward (1.3): one pass per Gaussian.
template <class T>
Projected<T> project_fwd(const Gaussians<T>& g, const Camera<T>& cam) {
  const size_t n = g.size();
  Projected<T> out;
  out.mean2d.assign(2 * n, T(0)), out.conic.assign(3 * n, T(0)), out.depth.assign(n, T(0));
  out.opacity.assign(n, T(0)), out.rgb.assign(3 * n, T(0)), out.radius.assign(n, 0);
  out.tile_rect.assign(4 * n, 0), out.clamped.assign(3 * n, 0);
  const size_t K = g.sh_coeffs();
  for (size_t i = 0; i < n; ++i) {
    const detail::Projection<T> p = detail::project_one(g, i, cam);
    if (!p.visible || std::isnan(g.opacity_logits[i])) continue;
    const T u = cam.fx * p.t[0] / p.t[2] + cam.cx, v = cam.fy * p.t[1] / p.t[2] + cam.cy;

    // 3-sigma radius and tile rectangle exactly as graphdeco (1.3 steps 6-7), applied to (u, v).
    // Tile indices are clamped in floating point first, so huge or negative coordinates never
    // reach an out-of-range conversion; overflowing inputs cull instead of poisoning tile lists.
    const T mid = (p.a + p.c) / 2;
    const T root = std::sqrt(std::max(detail::lit<T>(kMinEigenGap), mid * mid - p.det));
    const T r = std::ceil(detail::lit<T>(kSigmaExtent) * std::sqrt(mid + root));
    const T conic[3] = {p.c / p.det, -p.b / p.det, p.a / p.det};
    if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(r) || !std::isfinite(conic[0]) ||
        !std::isfinite(conic[1]) || !std::isfinite(conic[2]))
      continue;
    auto tile = [](T x, int hi) {
      return static_cast<int>(std::clamp(x / T(kTileSize), T(0), static_cast<T>(hi)));
    };
    const int radius = static_cast<int>(std::min(r, detail::lit<T>(1e9)));
    const int rect[4] = {tile(u - r, cam.tiles_x()), tile(v - r, cam.tiles_y()),
                         tile(u + r + (kTileSize - 1), cam.tiles_x()), tile(v + r + (kTileSize - 1), cam.tiles_y())};
    if ((rect[2] - rect[0]) * (rect[3] - rect[1]) == 0) continue;

    out.radius[i] = radius;
    for (size_t k = 0; k < 4; ++k) out.tile_rect[4 * i + k] = rect[k];
    out.mean2d[2 * i] = u, out.mean2d[2 * i + 1] = v;
    for (size_t k = 0; k < 3; ++k) out.conic[3 * i + k] = conic[k];
    out.depth[i] = p.t[2];
    out.opacity[i] = 1 / (1 + std::exp(-g.opacity_logits[i]));
    if (!g.colors.empty()) {
      for (size_t ch = 0; ch < 3; ++ch) out.rgb[3 * i + ch] = g.colors[3 * i + ch];
      continue;
    }
    std::array<T, 16> Y;
    detail::sh_basis<T>(g.sh_degree, p.dir, Y, nullptr);
    const size_t active = static_cast<size_t>((g.sh_degree + 1) * (g.sh_degree + 1));
    for (size_t ch = 0; ch < 3; ++ch) {
      T acc = detail::lit<T>(0.5);
      for (size_t k = 0; k < active; ++k) acc += Y[k] * g.sh[(i * K + k) * 3 + ch];
      out.clamped[3 * i + ch] = acc < 0 ? 1 : 0;
      out.rgb[3 * i + ch] = std::max(acc, T(0));
    }
  }
  return out;
}

namespace detail {

// Colour backward: SH coefficients (or the override colour) and the mean through the view direction.
template <class T>
void sh_bwd(const Gaussians<T>& g, size_t i, const Projection<T>& p, const Projected<T>& fwd, const T* v_rgb,
            GaussianGrads<T>& out, Vec3Of<T>& v_mu) {
  if (!g.colors.empty()) {
    for (size_t ch = 0; ch < 3; ++ch) out.v_colors[3 * i + ch] = v_rgb[ch];
    return;
  }
  T vc[3];
  for (size_t ch = 0; ch < 3; ++ch) vc[ch] = fwd.clamped[3 * i + ch] ? T(0) : v_rgb[ch];
  std::array<T, 16> Y;
  std::array<Vec3Of<T>, 16> dY;
  sh_basis<T>(g.sh_degree, p.dir, Y, &dY);
  const size_t K = g.sh_coeffs(), active = static_cast<size_t>((g.sh_degree + 1) * (g.sh_degree + 1));
  Vec3Of<T> v_dir{};
  for (size_t k = 0; k < active; ++k) {
    T f_dot = 0;
    for (size_t ch = 0; ch < 3; ++ch) {
      out.v_sh[(i * K + k) * 3 + ch] = Y[k] * vc[ch];
      f_dot += g.sh[(i * K + k) * 3 + ch] * vc[ch];
    }
    for (size_t a = 0; a < 3; ++a) v_dir[a] += dY[k][a] * f_dot;
  }
  // d = (mu - campos)/|mu - campos|: project onto the tangent plane and divide by the distance.
  const T radial = v_dir[0] * p.dir[0] + v_dir[1] * p.dir[1] + v_dir[2] * p.dir[2];
  for (size_t a = 0; a < 3; ++a) v_mu[a] += (v_dir[a] - p.dir[a] * radial) / p.dist;
}

// Rotation and scale backward from the symmetric 3D covariance cotangent G (Sigma = R S^2 R^T).
template <class T>
void covariance_bwd(size_t i, const Projection<T>& p, const Mat3<T>& G, GaussianGrads<T>& out) {
  // Sigma = N N^T with N = R S: v_N = 2 G N; v_R = v_N S; v_s_k = sum_r v_N[r][k] R[r][k].
  Mat3<T> vR{};
  Vec3Of<T> vs{};
  for (size_t r = 0; r < 3; ++r)
    for (size_t k = 0; k < 3; ++k) {
      T vN = 0;
      for (size_t l = 0; l < 3; ++l) vN += 2 * G[3 * r + l] * p.R[3 * l + k] * p.s[k];
      vR[3 * r + k] = vN * p.s[k];
      vs[k] += vN * p.R[3 * r + k];
    }
  for (size_t k = 0; k < 3; ++k) out.v_log_scales[3 * i + k] = vs[k] * p.s[k];

  // dR/dq for the unit quaternion (w, x, y, z), differentiated term by term from quat_to_rot.
  const T w = p.q[0], x = p.q[1], y = p.q[2], z = p.q[3];
  const auto& m = vR;
  const std::array<T, 4> vq = {
      2 * (-z * m[1] + y * m[2] + z * m[3] - x * m[5] - y * m[6] + x * m[7]),
      2 * (y * m[1] + z * m[2] + y * m[3] - 2 * x * m[4] - w * m[5] + z * m[6] + w * m[7] - 2 * x * m[8]),
      2 * (-2 * y * m[0] + x * m[1] + w * m[2] + x * m[3] + z * m[5] - w * m[6] + z * m[7] - 2 * y * m[8]),
      2 * (-2 * z * m[0] - w * m[1] + x * m[2] + w * m[3] - 2 * z * m[4] + y * m[5] + x * m[6] + y * m[7])};
  if (!(p.q_norm > 0)) return;  // identity fallback: the rotation does not depend on the raw quaternion
  // Normalisation Jacobian: keep the tangent part and divide by |raw q|.
  const T radial = vq[0] * p.q[0] + vq[1] * p.q[1] + vq[2] * p.q[2] + vq[3] * p.q[3];
  for (size_t k = 0; k < 4; ++k) out.v_quats[4 * i + k] = (vq[k] - p.q[k] * radial) / p.q_norm;
}

}  // namespace detail

// Preprocess backward: from the cotangents of the projected quantities to the raw parameters.
// Culled Gaussians get zero gradients.
template <class T>
GaussianGrads<T> project_bwd(const Gaussians<T>& g, const Camera<T>& cam, const Projected<T>& fwd,
                             const ProjectedGrads<T>& v) {
  using detail::Mat3;
  const size_t n = g.size();
  GaussianGrads<T> out;
  out.v_means.assign(3 * n, T(0)), out.v_log_scales.assign(3 * n, T(0)), out.v_quats.assign(4 * n, T(0));
  out.v_opacity_logits.assign(n, T(0)), out.v_sh.assign(g.sh.size(), T(0)), out.v_colors.assign(g.colors.size(), T(0));
  out.v_mean2d = v.v_mean2d;
  for (size_t i = 0; i < n; ++i) {
    if (fwd.radius[i] == 0) continue;
    const detail::Projection<T> p = detail::project_one(g, i, cam);
    const T o = fwd.opacity[i];
    out.v_opacity_logits[i] = v.v_opacity[i] * o * (1 - o);

    Vec3Of<T> v_mu{};
    detail::sh_bwd(g, i, p, fwd, &v.v_rgb[3 * i], out, v_mu);

    // Conic = inverse of S2 = [[a, b], [b, c]]: v_S2 = -S2^-1 G_conic S2^-1 with G_conic symmetric
    // (its off-diagonal holds half of v_B because B appears twice in the matrix).
    const T A = fwd.conic[3 * i], B = fwd.conic[3 * i + 1], C = fwd.conic[3 * i + 2];
    const T gA = v.v_conic[3 * i], gB = v.v_conic[3 * i + 1] / 2, gC = v.v_conic[3 * i + 2];
    const T yg00 = A * gA + B * gB, yg01 = A * gB + B * gC, yg10 = B * gA + C * gB, yg11 = B * gB + C * gC;
    const T va = -(yg00 * A + yg01 * B), vb_half = -(yg00 * B + yg01 * C), vc = -(yg10 * B + yg11 * C);
    const T G2[4] = {va, vb_half, vb_half, vc};  // symmetric cotangent of S2

    // S2 = M Sigma M^T: v_Sigma = M^T G2 M, v_M = 2 G2 M Sigma.
    Mat3<T> v_sigma{};
    for (size_t k = 0; k < 3; ++k)
      for (size_t l = 0; l < 3; ++l)
        for (size_t r0 = 0; r0 < 2; ++r0)
          for (size_t r1 = 0; r1 < 2; ++r1) v_sigma[3 * k + l] += p.M[3 * r0 + k] * G2[2 * r0 + r1] * p.M[3 * r1 + l];
    std::array<T, 6> v_M{};
    for (size_t r = 0; r < 2; ++r)
      for (size_t c = 0; c < 3; ++c)
        for (size_t r1 = 0; r1 < 2; ++r1)
          for (size_t k = 0; k < 3; ++k) v_M[3 * r + c] += 2 * G2[2 * r + r1] * p.M[3 * r1 + k] * p.sigma[3 * k + c];
    detail::covariance_bwd(i, p, v_sigma, out);

    // M = J W: v_J = v_M W^T; then J(t) with the guard-band clamp (a clamped ratio is constant).
    std::array<T, 6> v_J{};
    for (size_t r = 0; r < 2; ++r)
      for (size_t c = 0; c < 3; ++c)
        for (size_t k = 0; k < 3; ++k) v_J[3 * r + c] += v_M[3 * r + k] * p.W[3 * c + k];
    const T tx = p.t[0], ty = p.t[1], tz = p.t[2];
    Vec3Of<T> v_t{};
    // J00 = fx/tz, J02 = -fx*rx/tz with rx = tx/tz unless clamped (and the same for y).
    const T v_rx = -cam.fx / tz * v_J[2], v_ry = -cam.fy / tz * v_J[5];
    v_t[2] += -cam.fx / (tz * tz) * v_J[0] - cam.fy / (tz * tz) * v_J[4];
    v_t[2] += cam.fx * p.rx / (tz * tz) * v_J[2] + cam.fy * p.ry / (tz * tz) * v_J[5];
    if (!p.clamp_x) v_t[0] += v_rx / tz, v_t[2] += -v_rx * tx / (tz * tz);
    if (!p.clamp_y) v_t[1] += v_ry / tz, v_t[2] += -v_ry * ty / (tz * tz);
    // Screen-space mean (u = fx tx/tz + cx) and depth (= tz).
    const T vu = v.v_mean2d[2 * i], vv = v.v_mean2d[2 * i + 1];
    v_t[0] += cam.fx / tz * vu, v_t[1] += cam.fy / tz * vv;
    v_t[2] += -(cam.fx * tx * vu + cam.fy * ty * vv) / (tz * tz) + v.v_depth[i];

    for (size_t k = 0; k < 3; ++k)
      out.v_means[3 * i + k] = v_mu[k] + p.W[k] * v_t[0] + p.W[3 + k] * v_t[1] + p.W[6 + k] * v_t[2];
  }
  return out;
}

}  // namespace s4d::ref
