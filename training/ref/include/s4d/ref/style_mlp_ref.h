// CPU twin of the style rasterizer's per-pair pieces (ALGORITHMS.md 4.3-4.4): GOF's view-space
// quadric per Gaussian (shaders/splat/style_quadric.comp), the depth feature of t* per pixel ray, and
// the per-Gaussian MLP 2 -> 4 -> 4 -> 4 with its backward (shaders/include/raster_pair.glsl,
// raster_bwd.comp). Operations in the kernels' order, so float results agree to rounding.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "s4d/ref/splat_project_ref.h"
#include "s4d_style_splat.h"

namespace s4d::ref {

inline constexpr size_t kStyleMlpStride = S4D_STYLE_MLP_STRIDE;
inline constexpr size_t kStyleQuadricStride = S4D_STYLE_QUADRIC_STRIDE;

enum class StyleDepth : uint32_t { ndc = S4D_STYLE_DEPTH_NDC, relative = S4D_STYLE_DEPTH_RELATIVE };

// The style MLPs and their inputs' settings for one render.
template <class T>
struct StyleMlp {
  std::vector<T> weights;  // [N, 52], layout in s4d_style_splat.h
  T time{};                // MLP input x0
  StyleDepth depth = StyleDepth::ndc;
  T depth_scale = 1;       // StyleDepth::relative: feature = (t* - z_i) * depth_scale
  bool input_sigmoid = false;
};

// GOF's quadric of every Gaussian, [N, kStyleQuadricStride]: Q = R_v S^-2 R_v^T (upper triangle),
// b = -Q mu_v, zero padding; all zero where the projection culls.
template <class T>
std::vector<T> style_quadric(const Gaussians<T>& g, const Camera<T>& cam) {
  std::vector<T> out(kStyleQuadricStride * g.size(), T(0));
  for (size_t i = 0; i < g.size(); ++i) {
    const detail::Projection<T> p = detail::project_one(g, i, cam);
    if (!p.visible) continue;
    detail::Mat3<T> Rv{};  // W R, row-major
    for (size_t r = 0; r < 3; ++r)
      for (size_t c = 0; c < 3; ++c)
        Rv[3 * r + c] = p.W[3 * r] * p.R[c] + p.W[3 * r + 1] * p.R[3 + c] + p.W[3 * r + 2] * p.R[6 + c];
    T inv_s2[3];
    for (size_t k = 0; k < 3; ++k) inv_s2[k] = 1 / (p.s[k] * p.s[k] + detail::lit<T>(S4D_STYLE_SCALE_EPS));
    detail::Mat3<T> Q{};
    for (size_t r = 0; r < 3; ++r)
      for (size_t c = 0; c < 3; ++c)
        for (size_t k = 0; k < 3; ++k) Q[3 * r + c] += Rv[3 * r + k] * inv_s2[k] * Rv[3 * c + k];
    T* q = &out[kStyleQuadricStride * i];
    q[0] = Q[0], q[1] = Q[1], q[2] = Q[2], q[3] = Q[4], q[4] = Q[5], q[5] = Q[8];
    for (size_t r = 0; r < 3; ++r) q[6 + r] = -(Q[3 * r] * p.t[0] + Q[3 * r + 1] * p.t[1] + Q[3 * r + 2] * p.t[2]);
  }
  return out;
}

namespace detail {

template <class T>
T sigmoid(T v) {
  return 1 / (1 + std::exp(-v));
}

// The MLP's depth input on the ray (rx, ry, 1) for quadric q and centre depth z (see
// style_depth_feature in raster_pair.glsl): t* = -(b.r) / (r^T Q r), the centre depth where that
// is degenerate, then the NDC mapping (t* clamped to [near, far]) or (t* - z) * depth_scale.
template <class T>
T style_depth_feature(const T* q, T z, T rx, T ry, const StyleMlp<T>& mlp) {
  const T A = q[0] * rx * rx + q[3] * ry * ry + q[5] + 2 * (q[1] * rx * ry + q[2] * rx + q[4] * ry);
  const T bd = q[6] * rx + q[7] * ry + q[8];
  T t = -bd / A;
  if (!(A > 0) || !std::isfinite(t)) t = z;
  if (mlp.depth == StyleDepth::ndc) {
    const T t_near = lit<T>(S4D_STYLE_NDC_NEAR), t_far = lit<T>(S4D_STYLE_NDC_FAR);
    return t_far / (t_far - t_near) * (1 - t_near / std::clamp(t, t_near, t_far));
  }
  return (t - z) * mlp.depth_scale;
}

// Activations of one MLP evaluation: inputs (after the optional sigmoid), hidden layers, sigmoid(z).
template <class T>
struct MlpEval {
  std::array<T, 2> x{};
  std::array<T, 4> h1{}, h2{}, s{};
};

// w: one Gaussian's 52 weights.
template <class T>
MlpEval<T> style_mlp_fwd(const T* w, T x0, T x1, bool input_sigmoid) {
  MlpEval<T> m;
  m.x = input_sigmoid ? std::array<T, 2>{sigmoid(x0), sigmoid(x1)} : std::array<T, 2>{x0, x1};
  for (size_t r = 0; r < 4; ++r)
    m.h1[r] = sigmoid(w[S4D_STYLE_MLP_W1 + r] * m.x[0] + w[S4D_STYLE_MLP_W1 + 4 + r] * m.x[1] +
                      w[S4D_STYLE_MLP_B1 + r]);
  auto layer = [&](size_t W, size_t b, const std::array<T, 4>& in, size_t r) {
    T acc = 0;
    for (size_t c = 0; c < 4; ++c) acc += w[W + 4 * c + r] * in[c];
    return acc + w[b + r];
  };
  for (size_t r = 0; r < 4; ++r) m.h2[r] = sigmoid(layer(S4D_STYLE_MLP_W2, S4D_STYLE_MLP_B2, m.h1, r));
  for (size_t r = 0; r < 4; ++r) m.s[r] = sigmoid(layer(S4D_STYLE_MLP_W3, S4D_STYLE_MLP_B3, m.h2, r));
  return m;
}

// Adds the weight gradients of one evaluation with output cotangent dz = dL/dz to v_w (52 floats).
// The inputs are detached: no gradient to x.
template <class T>
void style_mlp_bwd(const T* w, const MlpEval<T>& m, const std::array<T, 4>& dz, T* v_w) {
  std::array<T, 4> da2{}, da1{};
  for (size_t c = 0; c < 4; ++c) {
    T dh2 = 0;
    for (size_t r = 0; r < 4; ++r) dh2 += w[S4D_STYLE_MLP_W3 + 4 * c + r] * dz[r];
    da2[c] = dh2 * m.h2[c] * (1 - m.h2[c]);
  }
  for (size_t c = 0; c < 4; ++c) {
    T dh1 = 0;
    for (size_t r = 0; r < 4; ++r) dh1 += w[S4D_STYLE_MLP_W2 + 4 * c + r] * da2[r];
    da1[c] = dh1 * m.h1[c] * (1 - m.h1[c]);
  }
  for (size_t r = 0; r < 4; ++r) {
    for (size_t c = 0; c < 2; ++c) v_w[S4D_STYLE_MLP_W1 + 4 * c + r] += da1[r] * m.x[c];
    v_w[S4D_STYLE_MLP_B1 + r] += da1[r];
    for (size_t c = 0; c < 4; ++c) v_w[S4D_STYLE_MLP_W2 + 4 * c + r] += da2[r] * m.h1[c];
    v_w[S4D_STYLE_MLP_B2 + r] += da2[r];
    for (size_t c = 0; c < 4; ++c) v_w[S4D_STYLE_MLP_W3 + 4 * c + r] += dz[r] * m.h2[c];
    v_w[S4D_STYLE_MLP_B3 + r] += dz[r];
  }
}

}  // namespace detail
}  // namespace s4d::ref
