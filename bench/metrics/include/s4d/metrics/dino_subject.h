// VBench's subject consistency (Huang et al. 2024, vbench/subject_consistency.py; METRICS.md 7)
// with DINO ViT-B/16 (nn::DinoVit). Each frame goes through VBench's dino_transform(224): RGB
// [0, 1] as uint8, torchvision Resize(224, antialias=False) (shorter side 224, longer side
// int(224 long / short), bilinear with align_corners False in PyTorch's float arithmetic, rounded
// back to uint8 half to even), / 255, ImageNet mean/std, no crop. f_i is the class token,
// L2-normalised. For frames i >= 1 of a video, s_i = (max(0, cos(f_{i-1}, f_i)) + max(0, cos(f_0,
// f_i))) / 2; the video's score is the mean of its s_i. Higher is better, in [0, 1].
// Weights: dino_vitbase16_pretrain.pth converted by tools/convert_weights.py (DINO's names).
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/dino_vit.h"
#include "s4d/util/chw.h"

namespace s4d::metrics {

inline constexpr uint32_t kDinoShortSide = 224;

// dino_transform(224) of an RGB frame: the network input [3, h, w]. Throws std::invalid_argument
// when the image is not RGB.
util::Chw<float> dino_transform(const io::ImageF& rgb);

// s_i of one frame from the unit features of the video's first frame, the previous one and it.
double subject_pair_score(const std::vector<double>& first, const std::vector<double>& previous,
                          const std::vector<double>& current);

class DinoSubject {
 public:
  // Throws as nn::DinoVit when the file does not hold a DINO ViT.
  DinoSubject(engine::Context& ctx, const io::SafetensorsFile& file, uint32_t heads = 0);

  // The L2-normalised class token of a frame (after dino_transform).
  std::vector<double> features(const io::ImageF& rgb) const;
  const nn::VitShape& shape() const { return vit_.shape(); }

 private:
  engine::Context& ctx_;
  nn::DinoVit vit_;
};

}  // namespace s4d::metrics
