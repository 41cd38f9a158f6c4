// CLIP-IQA+ (Wang, Chan & Loy, AAAI 2023; pyiqa `clipiqa+`, archs/clipiqa_arch.py; METRICS.md 2): a
// no-reference quality score in [0, 1], higher is better. pyiqa's CLIPIQA(model_type='clipiqa+',
// backbone='RN50') takes the RGB frame in [0, 1] at its own size (no resize or crop), normalises it
// with OpenAI CLIP's mean/std and runs CLIP's RN50 image tower without the position embedding
// (nn::ClipResnet). The learned prompt pair (CoOp context vectors around "Good photo." / "Bad photo.")
// goes through CLIP's text transformer once, independent of the image, so tools/convert_weights.py
// clipiqa_plus computes the two text features there and stores them: this file never runs a text
// tower. score = softmax_k(exp(logit_scale) cos(f, t_k))[0], with t_0 the "good" prompt's feature
// (exp(logit_scale) = 100 in OpenAI's RN50.pt); the cosines and softmax run on the host in double.
// Weights: clipiqa_plus.safetensors, CLIP's names for the image tower ("visual.*"), "logit_scale" []
// as stored (the log of the scale) and "text_features" [2, output_dim] (good, bad), not normalised.
#pragma once
#include <array>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/clip_resnet.h"

namespace s4d::metrics {

// OPENAI_CLIP_MEAN / OPENAI_CLIP_STD (CLIP's preprocessing; pyiqa archs/constants.py).
inline constexpr std::array<float, 3> kClipMean = {0.48145466f, 0.4578275f, 0.40821073f};
inline constexpr std::array<float, 3> kClipStd = {0.26862954f, 0.26130258f, 0.27577711f};

// softmax(scale [cos(f, t_good), cos(f, t_bad)])[0] in double; f and each t are normalised here (a
// zero vector throws std::invalid_argument, as its cosine is undefined).
double clipiqa_score(const std::vector<double>& image_feature, const std::vector<double>& good,
                     const std::vector<double>& bad, double logit_scale);

class ClipIqaPlus {
 public:
  // Throws std::runtime_error naming the file and tensor when a weight is missing or wrongly shaped.
  ClipIqaPlus(engine::Context& ctx, const io::SafetensorsFile& weights);
  const nn::ClipResnet& net() const { return net_; }
  // pyiqa's clipiqa+ of an RGB frame in [0, 1], at least nn::ClipResnet::kMinSize on each side.
  double operator()(const io::ImageF& rgb) const;

 private:
  engine::Context& ctx_;
  nn::ClipResnet net_;
  std::vector<double> good_, bad_;
  double logit_scale_ = 0;  // exp of the stored value
};

}  // namespace s4d::metrics
