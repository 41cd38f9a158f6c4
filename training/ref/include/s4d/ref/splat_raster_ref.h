// CPU twin of the 3DGS tile rasterizer family (ALGORITHMS.md 1.4-1.6; kernels
// shaders/splat/raster_{fwd,bwd}.comp): depth-sorted per-tile lists, front-to-back alpha blending per
// pixel, and its backward. raster_fwd/raster_bwd take a per-pair policy, as the kernels' variants do
// (raster_pair.glsl): PlainPairs here, the style MLP's StylePairs in style_raster_ref.h.
// render_fwd/render_bwd chain the preprocess (splat_project_ref.h) and the plain raster.
//
// Two cutoff variants:
//  * Cutoff::hard is the production rasterizer: skip power > 0, alpha = min(0.99, o*G), skip
//    alpha < 1/255, stop (without adding) once T*(1 - alpha) < 1e-4.
//  * Cutoff::smooth drops all four rules, so the image is a C1 function of the parameters and
//    finite differences are meaningful. The tile rectangles still apply; FD scenes make every
//    Gaussian's rectangle cover the whole image.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

#include "s4d/ref/splat_project_ref.h"

namespace s4d::ref {

enum class Cutoff { hard, smooth };

// Per-pixel forward outputs, row-major [H, W(, 3)].
template <class T>
struct Image {
  int width = 0, height = 0;
  std::vector<T> rgb;      // [H, W, 3] blended colour + T_final * background
  std::vector<T> alpha;    // [H, W] 1 - T_final
  std::vector<T> depth;    // [H, W] sum of depth_i * alpha_i * T_i (not divided by alpha)
  std::vector<int> count;  // [H, W] number of Gaussians blended
  std::vector<int> last;   // [H, W] 1 + position in the pixel's tile list of the last blended Gaussian
                           // (0 if none); the backward replays the list up to here
};

// Per-pixel cotangents. rgb is required; alpha and depth may be left empty (treated as zero).
template <class T>
struct ImageGrads {
  std::vector<T> v_rgb;    // [H, W, 3]
  std::vector<T> v_alpha;  // [H, W] or empty
  std::vector<T> v_depth;  // [H, W] or empty
};

// Per-tile Gaussian lists in blending order: a stable sort by depth, so ties keep input order.
// This is what the GPU's stable radix sort on (tile << 32 | depth bits) produces.
template <class T>
std::vector<std::vector<int>> tile_lists(const Projected<T>& proj, const Camera<T>& cam) {
  std::vector<int> order(proj.radius.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return proj.depth[static_cast<size_t>(a)] < proj.depth[static_cast<size_t>(b)];
  });
  std::vector<std::vector<int>> lists(static_cast<size_t>(cam.tiles_x() * cam.tiles_y()));
  for (int gi : order) {
    const size_t i = static_cast<size_t>(gi);
    if (proj.radius[i] == 0) continue;
    const int* rect = &proj.tile_rect[4 * i];
    for (int ty = rect[1]; ty < rect[3]; ++ty)
      for (int tx = rect[0]; tx < rect[2]; ++tx) lists[static_cast<size_t>(ty * cam.tiles_x() + tx)].push_back(gi);
  }
  return lists;
}

namespace detail {

// One (pixel, Gaussian) evaluation, shared by forward and backward so their skips agree.
template <class T>
struct Sample {
  bool skip = true;     // contributes nothing (power > 0 or alpha < 1/255 in the hard variant)
  bool clamped = false; // alpha was capped at kMaxAlpha: no gradient to conic, mean or opacity
  T alpha{}, G{}, dx{}, dy{};
};

// With opacity `opacity` in place of proj.opacity[i] (the style rasterizer's o + dO).
template <Cutoff kCutoff, class T>
Sample<T> sample(const Projected<T>& proj, size_t i, T px, T py, T opacity) {
  Sample<T> s;
  s.dx = proj.mean2d[2 * i] - px, s.dy = proj.mean2d[2 * i + 1] - py;
  const T A = proj.conic[3 * i], B = proj.conic[3 * i + 1], C = proj.conic[3 * i + 2];
  const T power = -(A * s.dx * s.dx + C * s.dy * s.dy) / 2 - B * s.dx * s.dy;
  s.G = std::exp(power);
  s.alpha = opacity * s.G;
  if constexpr (kCutoff == Cutoff::hard) {
    if (power > 0) return s;
    s.clamped = s.alpha > lit<T>(kMaxAlpha);
    s.alpha = std::min(s.alpha, lit<T>(kMaxAlpha));
    if (s.alpha < lit<T>(kMinAlpha)) return s;
  }
  s.skip = false;
  return s;
}

template <Cutoff kCutoff, class T>
Sample<T> sample(const Projected<T>& proj, size_t i, T px, T py) {
  return sample<kCutoff>(proj, i, px, py, proj.opacity[i]);
}

template <class T>
size_t pixel_tile(const Camera<T>& cam, int x, int y) {
  return static_cast<size_t>((y / kTileSize) * cam.tiles_x() + x / kTileSize);
}

}  // namespace detail

// One pixel as a pair policy sees it: its centre and its camera-space ray (x, y) at z = 1.
template <class T>
struct PixelRay {
  T px, py, rx, ry;
};

// One (pixel, Gaussian) pair as the blend uses it: the sample, the opacity it used and the colour
// it blends.
template <class T>
struct Pair {
  detail::Sample<T> s;
  T opacity{};
  std::array<T, 3> color{};
};

// The plain rasterizer's per-pair policy: the standard sample and the Gaussian's own colour; no
// cotangents beyond the projected ones. A policy provides `Pair` (a Pair<T> or one derived from it),
// sample<kCutoff>(i, pixel) and backward(i, pair, g_c, v_opacity), which gets each blended pair's
// colour cotangent g_c = alpha T dL/dC and dL/dopacity (0 where alpha was capped).
template <class T>
struct PlainPairs {
  using Pair = ref::Pair<T>;
  const Projected<T>& proj;

  template <Cutoff kCutoff>
  Pair sample(size_t i, const PixelRay<T>& pix) const {
    Pair p{detail::sample<kCutoff>(proj, i, pix.px, pix.py), proj.opacity[i], {}};
    for (size_t ch = 0; ch < 3; ++ch) p.color[ch] = proj.rgb[3 * i + ch];
    return p;
  }
  void backward(size_t, const Pair&, const std::array<T, 3>&, T) {}
};

namespace detail {

template <class T>
PixelRay<T> pixel_ray(const Camera<T>& cam, int x, int y) {
  const T px = static_cast<T>(x) + lit<T>(0.5), py = static_cast<T>(y) + lit<T>(0.5);
  return {px, py, (px - cam.cx) / cam.fx, (py - cam.cy) / cam.fy};
}

}  // namespace detail

// Raster forward (1.5): per pixel, blend its tile's list front to back, each pair as `pairs` says.
template <Cutoff kCutoff = Cutoff::hard, class T, class Pairs>
Image<T> raster_fwd(const Projected<T>& proj, const Camera<T>& cam, const std::array<T, 3>& background,
                    const Pairs& pairs) {
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
      const PixelRay<T> ray = detail::pixel_ray(cam, x, y);
      T trans = 1, color[3] = {0, 0, 0}, depth = 0;
      for (size_t k = 0; k < list.size(); ++k) {
        const size_t i = static_cast<size_t>(list[k]);
        const auto pair = pairs.template sample<kCutoff>(i, ray);
        const detail::Sample<T>& s = pair.s;
        if (s.skip) continue;
        const T next = trans * (1 - s.alpha);
        if (kCutoff == Cutoff::hard && next < detail::lit<T>(kMinTransmittance)) break;
        for (size_t ch = 0; ch < 3; ++ch) color[ch] += pair.color[ch] * s.alpha * trans;
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

template <Cutoff kCutoff = Cutoff::hard, class T>
Image<T> raster_fwd(const Projected<T>& proj, const Camera<T>& cam, const std::array<T, 3>& background) {
  return raster_fwd<kCutoff>(proj, cam, background, PlainPairs<T>{proj});
}

// Raster backward (1.6), computed the straightforward way: each pixel replays its forward list up
// to `last`, storing T_i, then walks back to front. Storing T_i avoids graphdeco's T/(1 - alpha)
// division, so the twin stays exact as alpha -> 1 (smooth variant). The pixel-alpha and background
// terms use T_final/(1 - alpha_i) = T_i * prod_{j>i}(1 - alpha_j), also without dividing.
// Where alpha was capped at 0.99 the conic, mean and opacity gradients are dropped (gsplat): the
// capped alpha does not depend on them, so this is the true gradient of the hard forward. The
// policy adds its own cotangents in pairs.backward().
template <Cutoff kCutoff = Cutoff::hard, class T, class Pairs>
ProjectedGrads<T> raster_bwd(const Projected<T>& proj, const Camera<T>& cam, const std::array<T, 3>& background,
                             const Image<T>& fwd, const ImageGrads<T>& v, Pairs& pairs) {
  const auto lists = tile_lists(proj, cam);
  ProjectedGrads<T> out(proj.radius.size());
  struct Entry {
    size_t i;
    typename Pairs::Pair pair;
    T trans;
  };
  std::vector<Entry> entries;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const size_t pix = static_cast<size_t>(y * cam.width + x);
      const auto& list = lists[detail::pixel_tile(cam, x, y)];
      const PixelRay<T> ray = detail::pixel_ray(cam, x, y);
      entries.clear();
      T trans = 1;
      for (size_t k = 0; k < static_cast<size_t>(fwd.last[pix]); ++k) {
        const size_t i = static_cast<size_t>(list[k]);
        const auto pair = pairs.template sample<kCutoff>(i, ray);
        if (pair.s.skip) continue;
        entries.push_back({i, pair, trans});
        trans *= 1 - pair.s.alpha;
      }

      const T* vc = &v.v_rgb[3 * pix];
      const T v_pix_alpha = v.v_alpha.empty() ? T(0) : v.v_alpha[pix];
      const T v_pix_depth = v.v_depth.empty() ? T(0) : v.v_depth[pix];
      const T bg_dot = background[0] * vc[0] + background[1] * vc[1] + background[2] * vc[2];
      T behind[3] = {0, 0, 0}, behind_depth = 0;  // what lies behind entry e, per unit of T_{e+1}
      T trans_behind = 1;                         // prod_{j>e}(1 - alpha_j)
      for (size_t e = entries.size(); e-- > 0;) {
        const auto& [i, pair, t_i] = entries[e];
        const detail::Sample<T>& s = pair.s;
        T v_alpha = t_i * (proj.depth[i] - behind_depth) * v_pix_depth + t_i * trans_behind * (v_pix_alpha - bg_dot);
        std::array<T, 3> g_c{};
        for (size_t ch = 0; ch < 3; ++ch) {
          v_alpha += t_i * (pair.color[ch] - behind[ch]) * vc[ch];
          g_c[ch] = s.alpha * t_i * vc[ch];
          out.v_rgb[3 * i + ch] += g_c[ch];
        }
        out.v_depth[i] += s.alpha * t_i * v_pix_depth;
        T v_opacity = 0;
        if (!s.clamped) {
          v_opacity = s.G * v_alpha;  // alpha = opacity * G
          out.v_opacity[i] += v_opacity;
          const T v_power = pair.opacity * s.G * v_alpha;
          const T A = proj.conic[3 * i], B = proj.conic[3 * i + 1], C = proj.conic[3 * i + 2];
          out.v_mean2d[2 * i] += -v_power * (A * s.dx + B * s.dy);
          out.v_mean2d[2 * i + 1] += -v_power * (B * s.dx + C * s.dy);
          out.v_conic[3 * i] += -v_power * s.dx * s.dx / 2;
          out.v_conic[3 * i + 1] += -v_power * s.dx * s.dy;
          out.v_conic[3 * i + 2] += -v_power * s.dy * s.dy / 2;
        }
        pairs.backward(i, pair, g_c, v_opacity);
        for (size_t ch = 0; ch < 3; ++ch) behind[ch] = s.alpha * pair.color[ch] + (1 - s.alpha) * behind[ch];
        behind_depth = s.alpha * proj.depth[i] + (1 - s.alpha) * behind_depth;
        trans_behind *= 1 - s.alpha;
      }
    }
  return out;
}

template <Cutoff kCutoff = Cutoff::hard, class T>
ProjectedGrads<T> raster_bwd(const Projected<T>& proj, const Camera<T>& cam, const std::array<T, 3>& background,
                             const Image<T>& fwd, const ImageGrads<T>& v) {
  PlainPairs<T> pairs{proj};
  return raster_bwd<kCutoff>(proj, cam, background, fwd, v, pairs);
}

// Full forward: preprocess then raster.
template <Cutoff kCutoff = Cutoff::hard, class T>
std::pair<Projected<T>, Image<T>> render_fwd(const Gaussians<T>& g, const Camera<T>& cam,
                                             const std::array<T, 3>& background) {
  Projected<T> proj = project_fwd(g, cam);
  Image<T> img = raster_fwd<kCutoff>(proj, cam, background);
  return {std::move(proj), std::move(img)};
}

// Full backward: gradients of the raw parameters (and of the screen-space means, in pixels).
template <Cutoff kCutoff = Cutoff::hard, class T>
GaussianGrads<T> render_bwd(const Gaussians<T>& g, const Camera<T>& cam, const std::array<T, 3>& background,
                            const Projected<T>& proj, const Image<T>& img, const ImageGrads<T>& v) {
  return project_bwd(g, cam, proj, raster_bwd<kCutoff>(proj, cam, background, img, v));
}

}  // namespace s4d::ref
