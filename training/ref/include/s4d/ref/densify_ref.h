// CPU twin of densification (shaders/densify/*.comp, host side training/trainers/densify): the statistics
// update from one view or a batch of views, clone / split / prune with the growth budget, and the
// opacity reset. It takes the kernels' own push constants (gpu::ClassifyParams, built by
// gpu::densify_classify_params) and calls the shared integer helpers of s4d_densify.h, so decisions,
// output order and random bits are identical; float arithmetic follows the kernels operation by
// operation, so copies are bit-exact and only split children's means (exp, log, sin, cos) differ.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "s4d/ref/splat_project_ref.h"
#include "s4d_densify.h"
#include "s4d_splat.h"

namespace s4d::ref {

// Every per-Gaussian array of a cloud in training, flat, in model::Attr order (means [N*3],
// log_scales [N*3], quats [N*4], opacity logits [N], sh [N*sh_width]); Adam moments in the same
// layouts; statistics grad_accum, grad_count, max_radius [N] each.
struct DensifyState {
  enum { kMeans, kLogScales, kQuats, kOpacity, kSh, kAttrs };
  enum { kGradAccum, kGradCount, kMaxRadius, kStats };
  std::array<std::vector<float>, kAttrs> param, m, v;
  std::array<std::vector<float>, kStats> stat;
  uint32_t sh_width = 3;  // floats of SH per Gaussian (K * 3)

  size_t size() const { return param[kOpacity].size(); }
  uint32_t width(int a) const { return a == kMeans || a == kLogScales ? 3u : a == kQuats ? 4u : a == kOpacity ? 1u : sh_width; }
  void resize(size_t n) {
    for (int a = 0; a < kAttrs; ++a) {
      param[a].assign(n * width(a), 0.0f);
      m[a].assign(n * width(a), 0.0f);
      v[a].assign(n * width(a), 0.0f);
    }
    for (auto& s : stat) s.assign(n, 0.0f);
  }
};

struct DensifyCounts {
  uint32_t before = 0, cloned = 0, split = 0, pruned = 0, demoted = 0, after = 0;
};

inline uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// densify_accumulate, S4D_ACCUM_VIEW: grad2d [N*S4D_G2D_STRIDE] pixel cotangents, radius [N].
inline void densify_accumulate_view(DensifyState& s, const std::vector<float>& grad2d, const std::vector<uint32_t>& radius,
                                    uint32_t width, uint32_t height) {
  const float hw = static_cast<float>(width) / 2, hh = static_cast<float>(height) / 2;
  for (size_t i = 0; i < s.size(); ++i) {
    if (radius[i] == 0) continue;
    const float gx = grad2d[i * S4D_G2D_STRIDE + S4D_G2D_XY] * hw, gy = grad2d[i * S4D_G2D_STRIDE + S4D_G2D_XY + 1] * hh;
    s.stat[DensifyState::kGradAccum][i] += std::sqrt(gx * gx + gy * gy);
    s.stat[DensifyState::kGradCount][i] += 1.0f;
    s.stat[DensifyState::kMaxRadius][i] = std::max(s.stat[DensifyState::kMaxRadius][i], static_cast<float>(radius[i]));
  }
}

// S4D_ACCUM_BATCH_ADD into scratch [N*S4D_ACCUM_SCRATCH_STRIDE] (sum x, sum y, largest radius).
inline void densify_accumulate_batch_add(std::vector<float>& scratch, const std::vector<float>& grad2d,
                                         const std::vector<uint32_t>& radius, uint32_t width, uint32_t height) {
  const float hw = static_cast<float>(width) / 2, hh = static_cast<float>(height) / 2;
  for (size_t i = 0; i < radius.size(); ++i) {
    if (radius[i] == 0) continue;
    float* sc = &scratch[i * S4D_ACCUM_SCRATCH_STRIDE];
    sc[0] += grad2d[i * S4D_G2D_STRIDE + S4D_G2D_XY] * hw;
    sc[1] += grad2d[i * S4D_G2D_STRIDE + S4D_G2D_XY + 1] * hh;
    sc[2] = std::max(sc[2], static_cast<float>(radius[i]));
  }
}

// S4D_ACCUM_BATCH_END: one statistics update per batch from the summed gradient; zeroes the scratch.
inline void densify_accumulate_batch_end(DensifyState& s, std::vector<float>& scratch) {
  for (size_t i = 0; i < s.size(); ++i) {
    float* sc = &scratch[i * S4D_ACCUM_SCRATCH_STRIDE];
    if (sc[2] > 0) {
      s.stat[DensifyState::kGradAccum][i] += std::sqrt(sc[0] * sc[0] + sc[1] * sc[1]);
      s.stat[DensifyState::kGradCount][i] += 1.0f;
      s.stat[DensifyState::kMaxRadius][i] = std::max(s.stat[DensifyState::kMaxRadius][i], sc[2]);
    }
    sc[0] = sc[1] = sc[2] = 0;
  }
}

// densify_classify for one Gaussian: the decision word and the outputs its demotion would save.
inline uint32_t densify_classify_one(const DensifyState& s, size_t i, const gpu::ClassifyParams& p, uint32_t* saved) {
  const float* ls = &s.param[DensifyState::kLogScales][3 * i];
  const float max_ls = std::max(std::max(ls[0], ls[1]), ls[2]);
  const float accum = s.stat[DensifyState::kGradAccum][i], count = s.stat[DensifyState::kGradCount][i];
  const float needed = p.grad_threshold * count;
  const bool grow = (p.rules & S4D_DENSIFY_RULE_GROW) != 0 && (count > 0 ? accum >= needed : 0.0f >= p.grad_threshold);
  const bool faint = (p.rules & S4D_DENSIFY_RULE_PRUNE_OPACITY) != 0 && s.param[DensifyState::kOpacity][i] < p.logit_min_opacity;
  const bool world = (p.rules & S4D_DENSIFY_RULE_PRUNE_WORLD) != 0, screen = (p.rules & S4D_DENSIFY_RULE_PRUNE_SCREEN) != 0;
  const bool orig_dies = faint || (screen && s.stat[DensifyState::kMaxRadius][i] > p.max_screen_radius) ||
                         (world && max_ls > p.log_max_world_scale);
  uint32_t f = orig_dies ? 0u : S4D_DENSIFY_ORIG_LIVES;
  if (grow) {
    const bool clone = max_ls <= p.log_dense_scale;
    const float new_ls = clone ? max_ls : max_ls - p.log_split_shrink;
    const bool new_dies = faint || (screen && 0.0f > p.max_screen_radius) || (world && new_ls > p.log_max_world_scale);
    f |= (clone ? S4D_DENSIFY_CLONE : S4D_DENSIFY_SPLIT) | (new_dies ? 0u : S4D_DENSIFY_NEW_LIVES);
  }
  *saved = gpu::densify_output_count(f) - gpu::densify_output_count(f & ~S4D_DENSIFY_GROW_MASK);
  return f;
}

// densify_split's standard normals for child `child` of source `index`.
inline std::array<float, 3> densify_split_normals(uint32_t seed, uint32_t index, uint32_t child) {
  float u[4];
  for (uint32_t d = 0; d < 4; ++d)
    u[d] = (static_cast<float>(gpu::densify_random_bits(seed, index, child, d) >> 8) + 1.0f) * (1.0f / 16777216.0f);
  const float two_pi = 6.28318530717958647692f;
  const float r0 = std::sqrt(-2.0f * std::log(u[0])), r1 = std::sqrt(-2.0f * std::log(u[2]));
  return {r0 * std::cos(two_pi * u[1]), r0 * std::sin(two_pi * u[1]), r1 * std::cos(two_pi * u[3])};
}

// Clone, split and prune (graphdeco densify_and_prune) with the growth budget; returns the new state
// (statistics zero, moments of new entries zero) and fills `counts` and, when given, `slots` with
// densify_map's slot words (source index | kind << S4D_DENSIFY_SLOT_SHIFT) per output.
// With keep_statistics, surviving originals keep their statistics (new entries start at zero).
inline DensifyState densify(const DensifyState& s, const gpu::ClassifyParams& p, uint32_t budget, uint32_t seed,
                            DensifyCounts* counts, std::vector<uint32_t>* slots = nullptr, bool keep_statistics = false) {
  const size_t n = s.size();
  if (p.n != n) throw std::invalid_argument("densify twin: params.n does not match the state");
  std::vector<uint32_t> flags(n), saved(n);
  uint64_t total = 0;
  for (size_t i = 0; i < n; ++i) {
    flags[i] = densify_classify_one(s, i, p, &saved[i]);
    total += gpu::densify_output_count(flags[i]);
  }
  DensifyCounts c;
  c.before = static_cast<uint32_t>(n);
  if (total > budget) {
    // Candidates by ascending mean gradient, ties in source order (the GPU's stable radix sort).
    std::vector<uint32_t> order;
    for (size_t i = 0; i < n; ++i)
      if (saved[i] > 0) order.push_back(static_cast<uint32_t>(i));
    auto key = [&](uint32_t i) {
      const float count = s.stat[DensifyState::kGradCount][i];
      return float_bits(count > 0 ? s.stat[DensifyState::kGradAccum][i] / count : 0.0f);
    };
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    const uint64_t excess = total - budget;
    uint64_t prefix = 0;
    for (uint32_t i : order) {
      if (prefix >= excess) break;
      prefix += saved[i];
      flags[i] &= ~S4D_DENSIFY_GROW_MASK;
      ++c.demoted;
    }
  }
  DensifyState out;
  out.sh_width = s.sh_width;
  uint32_t m_total = 0;
  for (uint32_t f : flags) m_total += gpu::densify_output_count(f);
  out.resize(m_total);
  if (slots) slots->clear();
  size_t j = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t f = flags[i], grow = f & S4D_DENSIFY_GROW_MASK;
    c.cloned += grow == S4D_DENSIFY_CLONE;
    c.split += grow == S4D_DENSIFY_SPLIT;
    c.pruned += gpu::densify_pruned_count(f);
    for (uint32_t k = 0; k < gpu::densify_output_count(f); ++k, ++j) {
      const uint32_t kind = gpu::densify_slot_kind(f, k);
      if (slots) slots->push_back(static_cast<uint32_t>(i) | (kind << S4D_DENSIFY_SLOT_SHIFT));
      for (int a = 0; a < DensifyState::kAttrs; ++a) {
        const uint32_t w = s.width(a);
        for (uint32_t e = 0; e < w; ++e) {
          out.param[a][j * w + e] = s.param[a][i * w + e];
          out.m[a][j * w + e] = kind == S4D_DENSIFY_SLOT_ORIGINAL ? s.m[a][i * w + e] : 0.0f;
          out.v[a][j * w + e] = kind == S4D_DENSIFY_SLOT_ORIGINAL ? s.v[a][i * w + e] : 0.0f;
        }
      }
      if (keep_statistics && kind == S4D_DENSIFY_SLOT_ORIGINAL)
        for (int st = 0; st < DensifyState::kStats; ++st) out.stat[st][j] = s.stat[st][i];
      if (kind != S4D_DENSIFY_SLOT_CHILD0 && kind != S4D_DENSIFY_SLOT_CHILD1) continue;
      const std::array<float, 3> nrm = densify_split_normals(seed, static_cast<uint32_t>(i), kind - S4D_DENSIFY_SLOT_CHILD0);
      const float* ls = &s.param[DensifyState::kLogScales][3 * i];
      const float d[3] = {std::exp(ls[0]) * nrm[0], std::exp(ls[1]) * nrm[1], std::exp(ls[2]) * nrm[2]};
      const float* q4 = &s.param[DensifyState::kQuats][4 * i];
      std::array<float, 4> q{};
      float norm = 0;
      detail::normalise_quat(q4, q, norm);  // as the rasterizer: tiny quaternions keep their rotation
      const float w = q[0], x = q[1], y = q[2], z = q[3];
      const float r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                             {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                             {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
      for (int row = 0; row < 3; ++row) {
        out.param[DensifyState::kMeans][3 * j + row] =
            (r[row][0] * d[0] + r[row][1] * d[1] + r[row][2] * d[2]) + s.param[DensifyState::kMeans][3 * i + row];
        out.param[DensifyState::kLogScales][3 * j + row] = ls[row] - p.log_split_shrink;
      }
    }
  }
  c.after = m_total;
  if (counts) *counts = c;
  return out;
}

// densify_reset_opacity: logit <- min(logit, gpu::densify_reset_logit(max_opacity)); opacity moments zeroed.
inline void densify_reset_opacity(DensifyState& s, float max_opacity) {
  const float cap = gpu::densify_reset_logit(max_opacity);
  for (float& l : s.param[DensifyState::kOpacity]) l = std::min(l, cap);
  std::fill(s.m[DensifyState::kOpacity].begin(), s.m[DensifyState::kOpacity].end(), 0.0f);
  std::fill(s.v[DensifyState::kOpacity].begin(), s.v[DensifyState::kOpacity].end(), 0.0f);
}

}  // namespace s4d::ref
