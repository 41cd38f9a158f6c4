// CPU twin of the style variants of the rasterizer family (ALGORITHMS.md 4.3; kernels
// shaders/splat/raster_{fwd,bwd}.comp with S4D_STYLE=1): splat_raster_ref.h's raster_fwd/raster_bwd
// with the StylePairs policy, where each (pixel, Gaussian) pair runs the Gaussian's MLP on (time,
// depth feature of t*) and blends colour c_i + dRGB with alpha = min(0.99, (o_i + dO) G),
// dRGB = 2 sigmoid(z_rgb) - 1, dO = sigmoid(z_3) - 0.5. The backward gives the usual projected
// cotangents (colour cotangent to c_i unchanged, dL/do' to the base opacity, mean and conic with o')
// plus the 52 MLP weight gradients per Gaussian; t* and the time are detached.
//
// Cutoff::hard and Cutoff::smooth as in splat_raster_ref.h. Zero W3 and b3 give dRGB = dO = 0: the
// plain rasterizer exactly.
#pragma once
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

#include "s4d/ref/splat_raster_ref.h"
#include "s4d/ref/style_mlp_ref.h"

namespace s4d::ref {

// Raster backward outputs: the projected cotangents and the MLP weight gradients [N, 52].
template <class T>
struct StyleRasterGrads {
  ProjectedGrads<T> g2d;
  std::vector<T> v_mlp;
};

// Full forward: the preprocess, the quadrics and the image.
template <class T>
struct StyleRender {
  Projected<T> proj;
  std::vector<T> quadric;  // [N, kStyleQuadricStride]
  Image<T> img;
};

// Full backward: gradients of the raw Gaussian parameters and of the MLP weights [N, 52].
template <class T>
struct StyleGaussianGrads {
  GaussianGrads<T> g;
  std::vector<T> v_mlp;
};

// The style variant's per-pair policy (see PlainPairs): the MLP on (time, depth feature of t* along
// the pixel ray), the standard sample with o' = o + dO and colour c + dRGB; backward() adds
// dL/dz = sigmoid'(z) (2 g_c, dL/do') through the MLP into v_mlp [N, 52].
template <class T>
struct StylePairs {
  struct Pair : ref::Pair<T> {
    detail::MlpEval<T> m;
  };
  const Projected<T>& proj;
  const std::vector<T>& quadric;
  const StyleMlp<T>& mlp;
  std::vector<T> v_mlp = std::vector<T>(kStyleMlpStride * proj.radius.size(), T(0));

  template <Cutoff kCutoff>
  Pair sample(size_t i, const PixelRay<T>& pix) const {
    Pair p;
    const T feature =
        detail::style_depth_feature(&quadric[kStyleQuadricStride * i], proj.depth[i], pix.rx, pix.ry, mlp);
    p.m = detail::style_mlp_fwd(&mlp.weights[kStyleMlpStride * i], mlp.time, feature, mlp.input_sigmoid);
    p.opacity = proj.opacity[i] + (p.m.s[3] - detail::lit<T>(0.5));
    for (size_t ch = 0; ch < 3; ++ch) p.color[ch] = proj.rgb[3 * i + ch] + (2 * p.m.s[ch] - 1);
    p.s = detail::sample<kCutoff>(proj, i, pix.px, pix.py, p.opacity);
    return p;
  }

  // Where alpha was capped at 0.99 dO gets no gradient either: the capped alpha does not depend on it.
  void backward(size_t i, const Pair& p, const std::array<T, 3>& g_c, T v_opacity) {
    std::array<T, 4> dz{};
    for (size_t ch = 0; ch < 3; ++ch) dz[ch] = p.m.s[ch] * (1 - p.m.s[ch]) * (2 * g_c[ch]);
    if (!p.s.clamped) dz[3] = p.m.s[3] * (1 - p.m.s[3]) * v_opacity;
    detail::style_mlp_bwd(&mlp.weights[kStyleMlpStride * i], p.m, dz, &v_mlp[kStyleMlpStride * i]);
  }
};

// Raster forward: raster_fwd with each pair's MLP.
template <Cutoff kCutoff = Cutoff::hard, class T>
Image<T> style_raster_fwd(const Projected<T>& proj, const std::vector<T>& quadric, const StyleMlp<T>& mlp,
                          const Camera<T>& cam, const std::array<T, 3>& background) {
  return raster_fwd<kCutoff>(proj, cam, background, StylePairs<T>{proj, quadric, mlp});
}

// Raster backward: raster_bwd with each pair's MLP, and the MLP weight gradients.
template <Cutoff kCutoff = Cutoff::hard, class T>
StyleRasterGrads<T> style_raster_bwd(const Projected<T>& proj, const std::vector<T>& quadric, const StyleMlp<T>& mlp,
                                     const Camera<T>& cam, const std::array<T, 3>& background, const Image<T>& fwd,
                                     const ImageGrads<T>& v) {
  StylePairs<T> pairs{proj, quadric, mlp};
  ProjectedGrads<T> g2d = raster_bwd<kCutoff>(proj, cam, background, fwd, v, pairs);
  return {std::move(g2d), std::move(pairs.v_mlp)};
}

// Full forward: preprocess, quadrics, raster.
template <Cutoff kCutoff = Cutoff::hard, class T>
StyleRender<T> render_style_fwd(const Gaussians<T>& g, const StyleMlp<T>& mlp, const Camera<T>& cam,
                                const std::array<T, 3>& background) {
  StyleRender<T> r{project_fwd(g, cam), style_quadric(g, cam), {}};
  r.img = style_raster_fwd<kCutoff>(r.proj, r.quadric, mlp, cam, background);
  return r;
}

// Full backward: raw-parameter gradients (through project_bwd) and the MLP weight gradients.
template <Cutoff kCutoff = Cutoff::hard, class T>
StyleGaussianGrads<T> render_style_bwd(const Gaussians<T>& g, const StyleMlp<T>& mlp, const Camera<T>& cam,
                                       const std::array<T, 3>& background, const StyleRender<T>& fwd,
                                       const ImageGrads<T>& v) {
  StyleRasterGrads<T> r = style_raster_bwd<kCutoff>(fwd.proj, fwd.quadric, mlp, cam, background, fwd.img, v);
  return {project_bwd(g, cam, fwd.proj, r.g2d), std::move(r.v_mlp)};
}

}  // namespace s4d::ref
