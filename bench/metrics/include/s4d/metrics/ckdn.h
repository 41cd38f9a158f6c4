// CKDN (Zheng et al., ICCV 2021; pyiqa `ckdn`, archs/ckdn_arch.py; METRICS.md 8): a degraded-
// reference quality score in [0, 1], higher is better, asymmetric. pyiqa's ckdn(x, y) preprocesses
// (CKDN._default_preprocess) on float RGB in [0, 1]: torchvision resize of the shorter side to
// floor(288 / 0.875) = 329 (the longer to int(329 * long / short)), x ("restored", the distorted
// image) bicubic with antialiasing (torchvision >= 0.17's default: the PIL-style cubic, a = -0.5,
// widened by the scale when shrinking), y (the reference) nearest; a 288 x 288 centre crop (offsets
// round((side - 288) / 2), half to even); ImageNet mean/std. Then nn::CkdnNet and a sigmoid (host).
// The resizes and crop run on the host in double, since they are a small part of a frame's cost.
#pragma once
#include <cstdint>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/ckdn_net.h"

namespace s4d::metrics {

inline constexpr int kCkdnResize = 329;  // int(floor(288 / 0.875))
inline constexpr int kCkdnCrop = 288;

enum class ResizeFilter { bicubic_antialias, nearest };

// torchvision.transforms.functional.resize(img, shorter) on a float [C, H, W] tensor: the shorter
// side becomes `shorter`, the longer int(shorter * long / short); unchanged when already that size.
// bicubic_antialias: torch's _upsample_bicubic2d_aa (separable, weights normalised to sum 1, not
// clamped); nearest: F.interpolate's source index min(floor(dst * float(in / out)), in - 1), in float
// as torch computes it. Throws std::invalid_argument for an empty image or a non-positive size.
io::ImageF resize_shorter_side(const io::ImageF& image, int shorter, ResizeFilter filter);

// torchvision center_crop(img, size) of an image at least size x size: top = round((h - size) / 2),
// left = round((w - size) / 2), Python's round (half to even). Throws std::invalid_argument when
// smaller.
io::ImageF center_crop(const io::ImageF& image, int size);

class Ckdn {
 public:
  // Throws std::runtime_error naming the file and tensor when a weight is missing or wrongly shaped.
  Ckdn(engine::Context& ctx, const io::SafetensorsFile& weights);
  // pyiqa's ckdn(restored, reference): both RGB in [0, 1], any sizes (each is resized and cropped).
  double operator()(const io::ImageF& restored, const io::ImageF& reference) const;

 private:
  engine::Context& ctx_;
  nn::CkdnNet net_;
};

}  // namespace s4d::metrics
