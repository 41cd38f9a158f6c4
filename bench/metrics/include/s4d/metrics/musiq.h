// MUSIQ (Ke et al., ICCV 2021; pyiqa `musiq` with the KonIQ weights and `musiq-paq2piq`;
// METRICS.md 3): a no-reference quality score, ~0..100, higher is better. pyiqa's MUSIQ.forward in
// eval mode on RGB in [0, 1] (multiscale_trans_util.get_multiscale_patches): x := 2 (x - 0.5); the
// scales with longer side 224 and 384 (sorted; scale ids 0, 1), each rh = round(h L / max(h, w)),
// rw likewise (Python's round, half to even), resized by F.interpolate bicubic (align_corners False,
// no antialiasing), then the image itself (scale id 2, every patch); each cut into 32x32 patches with
// TF 'SAME' zero padding (ceil(side / 32) patches, the padding split floor before / ceil after);
// each patch's hashed position row * 10 + column, row = nearest index of the patch row in the 10-row
// grid (F.interpolate nearest: floor(i 10 / count_h)), column likewise. pyiqa pads the two resized
// scales to ceil(L / 32)^2 tokens with mask 0; a masked key's score is set to -1e3 before the
// softmax, so its weight exp(-1e3 - max) is exactly 0 in float and masked tokens change no other
// token: they are left out here. The preprocessing runs on the host in double.
#pragma once
#include <array>
#include <cstdint>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/musiq_net.h"

namespace s4d::metrics {

inline constexpr std::array<uint32_t, 2> kMusiqLongerSides = {224, 384};

// The patches of an RGB image in [0, 1] (any size), positions hashed onto a grid x grid grid: the
// 224 scale's, the 384 scale's, then the image's own, each row-major. Throws std::invalid_argument
// when the image is not RGB.
nn::MusiqPatches musiq_patches(const io::ImageF& rgb, uint32_t grid);

class Musiq {
 public:
  // Throws std::runtime_error naming the file and tensor when a weight is missing or wrongly shaped.
  Musiq(engine::Context& ctx, const io::SafetensorsFile& weights);
  const nn::MusiqShape& shape() const { return net_.shape(); }
  // pyiqa's musiq (or musiq-paq2piq, by the weights) of an RGB image in [0, 1].
  double operator()(const io::ImageF& rgb) const;

 private:
  nn::MusiqNet net_;
};

}  // namespace s4d::metrics
