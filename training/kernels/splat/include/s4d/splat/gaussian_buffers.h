// One per-Gaussian buffer set indexed by attribute. Every per-Gaussian array on the device (the
// rasterizer's parameters and gradients, the deformation field's canonical and deformed Gaussians,
// the trained cloud's parameters, gradients and Adam moments) is a PerAttr: a std::array indexed by
// Attr, so code that treats the attributes alike loops over them, and code that names one writes
// set[Attr::means]. The facts of each attribute (its name, floats per Gaussian) live here once, from
// the layouts of shaders/shared/s4d_splat.h and s4d_style_splat.h.
#pragma once
#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d_splat.h"
#include "s4d_style_splat.h"

namespace s4d::splat {

// The per-Gaussian attributes, flat float arrays. The first five are a Gaussian cloud's
// (io::GaussianCloud, a checkpoint's, the trainer's Adam groups and the deformation field's heads,
// in this order); colors replace the SH colour when set; style_mlp holds the Style Gaussians' MLPs.
enum class Attr : uint32_t { means, log_scales, quats, opacity_logits, sh, colors, style_mlp };
inline constexpr uint32_t kAttrCount = 7;
inline constexpr uint32_t kCloudAttrCount = 5;
inline constexpr std::array<Attr, kCloudAttrCount> kCloudAttrs = {Attr::means, Attr::log_scales, Attr::quats,
                                                                  Attr::opacity_logits, Attr::sh};

constexpr uint32_t index(Attr a) { return static_cast<uint32_t>(a); }

// PerAttr<T, kCloudAttrCount> relies on it: the cloud's attributes are the first ones, in order.
static_assert([] {
  for (uint32_t i = 0; i < kCloudAttrCount; ++i)
    if (index(kCloudAttrs[i]) != i) return false;
  return true;
}());

// The attribute's name in buffer names, checkpoints and errors ("means", "opacity_logits", ...).
constexpr const char* attr_name(Attr a) {
  constexpr const char* kNames[kAttrCount] = {"means", "log_scales", "quats", "opacity_logits",
                                              "sh",    "colors",     "style_mlp"};
  return kNames[index(a)];
}

// Floats per Gaussian; sh's depends on K, the SH coefficients stored per channel.
constexpr uint32_t attr_floats(Attr a, uint32_t sh_coeffs) {
  constexpr uint32_t kFloats[kAttrCount] = {S4D_MEANS_FLOATS, S4D_LOG_SCALES_FLOATS, S4D_QUATS_FLOATS,
                                            S4D_OPACITY_LOGITS_FLOATS, 0, S4D_COLORS_FLOATS, S4D_STYLE_MLP_STRIDE};
  return a == Attr::sh ? S4D_SH_FLOATS_PER_COEFF * sh_coeffs : kFloats[index(a)];
}

// How a buffer holds an attribute's floats: f32, or f16 (IEEE halves packed two to a 32-bit word,
// io::pack_halves's layout). f16 is the render side's storage of sh and style_mlp only: the
// rasterizer's forward reads it (the _half kernel variants); everything that trains reads f32.
enum class Storage : uint32_t { f32, f16 };

// Bytes of `n` Gaussians' attribute `a` stored as `s` (f16 rounds up to whole 32-bit words).
constexpr size_t attr_bytes(Attr a, uint32_t sh_coeffs, size_t n, Storage s = Storage::f32) {
  const size_t floats = n * attr_floats(a, sh_coeffs);
  return s == Storage::f32 ? floats * 4 : (floats + 1) / 2 * 4;
}

// One T per attribute, indexed by Attr. N = kCloudAttrCount holds the cloud's attributes only.
template <class T, uint32_t N = kAttrCount>
struct PerAttr {
  std::array<T, N> items{};

  T& operator[](Attr a) {
    assert(index(a) < N);
    return items[index(a)];
  }
  const T& operator[](Attr a) const {
    assert(index(a) < N);
    return items[index(a)];
  }
};

// Views of device buffers, one pointer per attribute (null: absent). B is engine::Buffer for outputs
// (gradients, deformed values) and const engine::Buffer for inputs.
template <class B>
using GaussianBuffers = PerAttr<B*>;

// Gradients of per-Gaussian parameters, same layouts (the rasterizer's backward writes them, the
// deformation field's backward reads them).
using GaussianGrads = GaussianBuffers<engine::Buffer>;

// A host cloud's arrays by attribute.
inline PerAttr<const std::vector<float>*, kCloudAttrCount> cloud_arrays(const io::GaussianCloud& c) {
  return {{&c.means, &c.log_scales, &c.quats, &c.opacity_logits, &c.sh}};
}
inline PerAttr<std::vector<float>*, kCloudAttrCount> cloud_arrays(io::GaussianCloud& c) {
  return {{&c.means, &c.log_scales, &c.quats, &c.opacity_logits, &c.sh}};
}

}  // namespace s4d::splat
