// The learned metrics `style4d bench` computes natively on the GPU from --metric-weights DIR:
// content_lpips (stylised vs original frame) and style_lpips (frame vs the style image resized to
// the frame) with LPIPS-VGG, dists (consecutive stylised frames, DISTS(f_t+1, f_t)),
// style_loss_gram (frame vs style image) with VGG19, dino_score (VBench subject consistency of
// the stylised frames) with DINO ViT-B/16, ckdn (pyiqa's ckdn(frame, style image)), clipiqa_plus
// (pyiqa's clipiqa+ of each stylised frame, CLIP RN50) and musiq / musiq_paq2piq (pyiqa's MUSIQ of
// each stylised frame, KonIQ / PaQ-2-PiQ weights). Each network
// loads once per call; a key whose
// files are absent from DIR (or with no DIR) gets the reason and the file names. Files, in DIR, as
// tools/convert_weights.py writes them from:
//   vgg16.safetensors           torchvision vgg16-397923af.pth    ("features.<i>.weight/bias")
//   lpips_vgg.safetensors       LPIPS weights/v0.1/vgg.pth        ("lin<l>.model.1.weight")
//   alexnet.safetensors         torchvision alexnet-owt-7be5be79.pth  ("features.<i>"; --lpips-net alex)
//   lpips_alex.safetensors      LPIPS weights/v0.1/alex.pth       (--lpips-net alex)
//   dists.safetensors           DISTS_pytorch/weights.pt          ("alpha", "beta")
//   vgg_normalised.safetensors  AdaIN vgg_normalised.pth          ("0", "2", ...; --gram-vgg normalised, default)
//   vgg19.safetensors           torchvision vgg19-dcbb9e9d.pth    ("features.<i>"; --gram-vgg torchvision)
//   dino_vitb16.safetensors     DINO dino_vitbase16_pretrain.pth  ("cls_token", "blocks.<i>.attn.qkv", ...)
//   ckdn.safetensors            pyiqa CKDN_model_best-38b27dc6.pth  ("net.qse_1.weight", ...)
//   musiq.safetensors           pyiqa musiq_koniq_ckpt-e95806b9.pth  ("conv_root.weight", ...)
//   musiq_paq2piq.safetensors   pyiqa musiq_paq2piq_ckpt-364c0c84.pth
//   clipiqa_plus.safetensors    OpenAI RN50.pt + pyiqa CLIP-IQA+_learned_prompts-603f3273.pth
//                               ("visual.conv1.weight", ..., "logit_scale", "text_features")
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/metrics/dino_subject.h"
#include "s4d/metrics/ckdn.h"
#include "s4d/metrics/clipiqa.h"
#include "s4d/metrics/dists.h"
#include "s4d/metrics/gram_loss.h"
#include "s4d/metrics/lpips.h"
#include "s4d/metrics/musiq.h"

namespace s4d::bench {

struct NativeLearnedOptions {
  std::optional<std::filesystem::path> weights_dir;  // --metric-weights
  metrics::GramBackbone gram = metrics::GramBackbone::vgg_normalised;
  metrics::LpipsNet lpips = metrics::LpipsNet::vgg;
  metrics::LpipsInput lpips_input = metrics::LpipsInput::signed_unit;
};

// The keys NativeLearned may compute.
const std::vector<std::string>& native_learned_keys();

class NativeLearned {
 public:
  // Loads the networks whose files are in the folder. Throws std::runtime_error naming the file and
  // tensor when a present file is unreadable or holds a missing or wrongly shaped tensor, and
  // std::invalid_argument when the folder does not exist.
  NativeLearned(engine::Context& ctx, const NativeLearnedOptions& options);

  // Keys this call cannot compute, with why and what to supply.
  const std::map<std::string, std::string>& unavailable() const { return unavailable_; }
  bool computes(const std::string& key) const;
  // What computed `key` (impl) and how (convention), for metrics_info.
  std::string impl(const std::string& key) const;
  std::string convention(const std::string& key) const;

  // Appends one frame's values to per_frame for the keys in `keys` (empty: all): content_lpips
  // (stylised, original), clipiqa_plus, musiq and musiq_paq2piq (stylised); with a style image
  // style_lpips, style_loss_gram and ckdn; when the frame
  // follows the previous call's frame in its video (`follows`), dists of the pair and dino_score's
  // s_i (against the video's first frame and the previous one). The style image's
  // features are cached per path and size, the previous frame's DISTS stages until the next call.
  void score_frame(const io::ImageF& stylised, const io::ImageF& original, const std::filesystem::path& style_image,
                   bool follows, const std::vector<std::string>& keys,
                   std::map<std::string, std::vector<double>>& per_frame) const;

 private:
  NativeLearnedOptions options_;
  std::unique_ptr<metrics::Lpips> lpips_;
  std::unique_ptr<metrics::GramStyleLoss> gram_;
  std::unique_ptr<metrics::Dists> dists_;
  std::unique_ptr<metrics::DinoSubject> dino_;
  std::unique_ptr<metrics::Ckdn> ckdn_;
  std::unique_ptr<metrics::Musiq> musiq_, musiq_paq2piq_;
  std::unique_ptr<metrics::ClipIqaPlus> clipiqa_;
  std::map<std::string, std::string> unavailable_;
  // Style image caches: the image itself, its LPIPS taps at a frame size, its Gram matrices.
  mutable std::filesystem::path style_path_;
  mutable io::ImageF style_;
  mutable std::map<std::pair<int, int>, metrics::LpipsFeatures> style_lpips_;
  mutable std::optional<metrics::GramSet> style_gram_;
  mutable std::optional<metrics::DistsFeatures> previous_;  // the last frame's DISTS stages
  mutable std::optional<std::vector<double>> dino_first_;  // the video's first frame's DINO features
  mutable std::vector<double> dino_previous_;
};

}  // namespace s4d::bench
