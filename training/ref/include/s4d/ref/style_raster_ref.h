// CPU twin of the style rasterizer (ALGORITHMS.md 4.3; kernels shaders/splat/style_raster_{fwd,bwd}.comp):
// the tile rasterizer of splat_raster_ref.h where each (pixel, Gaussian) pair runs the Gaussian's MLP
// on (time, depth feature of t*) and blends colour c_i + dRGB with alpha = min(0.99, (o_i + dO) G),
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

namespace detail {

// One (pixel, Gaussian) pair: the MLP's activations and the standard sample with opacity o'.
template <class T>
struct StyleSample {
  Sample<T> s;
  MlpEval<T> m;
  T opacity{};  // o' = o + dO
  std::array<T, 3> color{};  // c_i + dRGB
};

template <Cutoff kCutoff, class T>
StyleSample<T> style_sample(const Projected<T>& proj, const std::vector<T>& quadric, const StyleMlp<T>& mlp, size_t i,
                            T px, T py, T rx, T ry) {
  StyleSample<T> out;
  const T feature = style_depth_feature(&quadric[kStyleQuadricStride * i], proj.depth[i], rx, ry, mlp);
  out.m = style_mlp_fwd(&mlp.weights[kStyleMlpStride * i], mlp.time, feature, mlp.input_sigmoid);
  out.opacity = proj.opacity[i] + (out.m.s[3] - lit<T>(0.5));
  for (size_t ch = 0; ch < 3; ++ch) out.color[ch] = proj.rgb[3 * i + ch] + (2 * out.m.s[ch] - 1);
  out.s = sample<kCutoff>(proj, i, px, py, out.opacity);
  return out;
}

}  // namespace detail

// Raster forward: per pixel, blend its tile's list front to back with each pair's MLP.
template <Cutoff kCutoff = Cutoff::hard, class T>
Image<T> style_raster_fwd(const Projected<T>& proj, const std::vector<T>& quadric, const StyleMlp<T>& mlp,
                          const Camera<T>& cam, const std::array<T, 3>& background) {
  const auto lists = tile_lists(proj, cam);
  Image<T> img;
  img.width = cam.width, img.height = cam.height;
  const size_t npix = static_cast<size_t>(cam.width * cam.height);
  img.rgb.assign(3 * npix, T(0)), img.alpha.assign(npix, T(0)), img.depth.assign(npix, T(0));
  img.count.assign(npix, 0), img.last.assign(npix, 0);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const size_t pix = static_cast<size_t>(y * cam.width + x);
      const auto& list = lists[detail::pixel_tile(cam, x, y)];
      const T px = static_cast<T>(x) + detail::lit<T>(0.5), py = static_cast<T>(y) + detail::lit<T>(0.5);
      const T rx = (px - cam.cx) / cam.fx, ry = (py - cam.cy) / cam.fy;
      T trans = 1, color[3] = {0, 0, 0}, depth = 0;
      for (size_t k = 0; k < list.size(); ++k) {
        const size_t i = static_cast<size_t>(list[k]);
        const auto st = detail::style_sample<kCutoff>(proj, quadric, mlp, i, px, py, rx, ry);
        const detail::Sample<T>& s = st.s;
        if (s.skip) continue;
        const T next = trans * (1 - s.alpha);
        if (kCutoff == Cutoff::hard && next < detail::lit<T>(kMinTransmittance)) break;
        // Same association as raster_fwd, so dRGB = dO = 0 reproduces it bit for bit.
        for (size_t ch = 0; ch < 3; ++ch) color[ch] += st.color[ch] * s.alpha * trans;
        depth += proj.depth[i] * s.alpha * trans;
        trans = next;
        ++img.count[pix];
        img.last[pix] = static_cast<int>(k + 1);
      }
      for (size_t ch = 0; ch < 3; ++ch) img.rgb[3 * pix + ch] = color[ch] + trans * background[ch];
      img.alpha[pix] = 1 - trans, img.depth[pix] = depth;
    }
  return img;
}

// Raster backward, the straightforward way of raster_bwd (stored T_i, no division), plus
// dL/dz = sigmoid'(z) (2 g_c, dL/do') through each pair's MLP. Where alpha was capped at 0.99 the
// conic, mean, opacity and dO gradients are dropped: the capped alpha depends on none of them.
template <Cutoff kCutoff = Cutoff::hard, class T>
StyleRasterGrads<T> style_raster_bwd(const Projected<T>& proj, const std::vector<T>& quadric, const StyleMlp<T>& mlp,
                                     const Camera<T>& cam, const std::array<T, 3>& background, const Image<T>& fwd,
                                     const ImageGrads<T>& v) {
  const auto lists = tile_lists(proj, cam);
  const size_t n = proj.radius.size();
  StyleRasterGrads<T> out{ProjectedGrads<T>(n), std::vector<T>(kStyleMlpStride * n, T(0))};
  ProjectedGrads<T>& g2d = out.g2d;
  struct Entry {
    size_t i;
    detail::StyleSample<T> st;
    T trans;
  };
  std::vector<Entry> entries;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const size_t pix = static_cast<size_t>(y * cam.width + x);
      const auto& list = lists[detail::pixel_tile(cam, x, y)];
      const T px = static_cast<T>(x) + detail::lit<T>(0.5), py = static_cast<T>(y) + detail::lit<T>(0.5);
      const T rx = (px - cam.cx) / cam.fx, ry = (py - cam.cy) / cam.fy;
      entries.clear();
      T trans = 1;
      for (size_t k = 0; k < static_cast<size_t>(fwd.last[pix]); ++k) {
        const size_t i = static_cast<size_t>(list[k]);
        const auto st = detail::style_sample<kCutoff>(proj, quadric, mlp, i, px, py, rx, ry);
        if (st.s.skip) continue;
        entries.push_back({i, st, trans});
        trans *= 1 - st.s.alpha;
      }

      const T* vc = &v.v_rgb[3 * pix];
      const T v_pix_alpha = v.v_alpha.empty() ? T(0) : v.v_alpha[pix];
      const T v_pix_depth = v.v_depth.empty() ? T(0) : v.v_depth[pix];
      const T bg_dot = background[0] * vc[0] + background[1] * vc[1] + background[2] * vc[2];
      T behind[3] = {0, 0, 0}, behind_depth = 0;  // what lies behind entry e, per unit of T_{e+1}
      T trans_behind = 1;                         // prod_{j>e}(1 - alpha_j)
      for (size_t e = entries.size(); e-- > 0;) {
        const auto& [i, st, t_i] = entries[e];
        const detail::Sample<T>& s = st.s;
        T v_alpha = t_i * (proj.depth[i] - behind_depth) * v_pix_depth + t_i * trans_behind * (v_pix_alpha - bg_dot);
        std::array<T, 4> dz{};
        for (size_t ch = 0; ch < 3; ++ch) {
          v_alpha += t_i * (st.color[ch] - behind[ch]) * vc[ch];
          const T g_c = s.alpha * t_i * vc[ch];
          g2d.v_rgb[3 * i + ch] += g_c;
          dz[ch] = st.m.s[ch] * (1 - st.m.s[ch]) * (2 * g_c);
        }
        g2d.v_depth[i] += s.alpha * t_i * v_pix_depth;
        if (!s.clamped) {
          const T v_opacity = s.G * v_alpha;  // alpha = (o + dO) G
          g2d.v_opacity[i] += v_opacity;
          dz[3] = st.m.s[3] * (1 - st.m.s[3]) * v_opacity;
          const T v_power = st.opacity * s.G * v_alpha;
          const T A = proj.conic[3 * i], B = proj.conic[3 * i + 1], C = proj.conic[3 * i + 2];
          g2d.v_mean2d[2 * i] += -v_power * (A * s.dx + B * s.dy);
          g2d.v_mean2d[2 * i + 1] += -v_power * (B * s.dx + C * s.dy);
          g2d.v_conic[3 * i] += -v_power * s.dx * s.dx / 2;
          g2d.v_conic[3 * i + 1] += -v_power * s.dx * s.dy;
          g2d.v_conic[3 * i + 2] += -v_power * s.dy * s.dy / 2;
        }
        detail::style_mlp_bwd(&mlp.weights[kStyleMlpStride * i], st.m, dz, &out.v_mlp[kStyleMlpStride * i]);
        for (size_t ch = 0; ch < 3; ++ch) behind[ch] = s.alpha * st.color[ch] + (1 - s.alpha) * behind[ch];
        behind_depth = s.alpha * proj.depth[i] + (1 - s.alpha) * behind_depth;
        trans_behind *= 1 - s.alpha;
      }
    }
  return out;
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
