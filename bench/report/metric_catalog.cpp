#include "s4d/bench/metric_catalog.h"

#include <stdexcept>

namespace s4d::bench {

namespace {

// The learned metrics: no native network is built yet, and the pyiqa bridge (--python) is not built
// yet either, so each says which files its native implementation will load.
std::string needs(const std::string& what, const std::string& files) {
  return "not built yet: the native " + what + " network is not implemented, and the pyiqa bridge (--python) is not built; it will need " +
         files + " (PyTorch state dicts converted to safetensors with their original names)";
}

std::vector<MetricEntry> build() {
  return {
      {"uiqm", "UIQM", true, "native (s4d::metrics::uiqm)", "", std::nullopt},
      {"clipiqa_plus", "CLIP-IQA+", true, "pyiqa clipiqa+ (RN50)", "[0,1] RGB, no resize, CLIP mean/std",
       needs("CLIP-IQA+", "CLIP-IQA+_learned_prompts-603f3273.pth and OpenAI RN50.pt")},
      {"musiq", "MUSIQ", true, "pyiqa musiq (KonIQ)", "multi-scale 224/384 + full resolution",
       needs("MUSIQ", "musiq_koniq_ckpt-e95806b9.pth")},
      {"qalign", "Q-Align", true, "pyiqa qalign, task aesthetic", "q-future/one-align (8B parameters)",
       std::string("not built yet: Q-Align (q-future/one-align, about 16 GB) is planned through the pyiqa bridge "
                   "(--python) only, which is not built yet")},
      {"musiq_paq2piq", "MUSIQ-PaQ2PiQ", true, "pyiqa musiq-paq2piq", "multi-scale 224/384 + full resolution",
       needs("MUSIQ-PaQ2PiQ", "musiq_paq2piq_ckpt-364c0c84.pth")},
      {"dists", "DISTS", false, "DISTS (VGG16 + alpha/beta)", "consecutive frames DISTS(f_t+1, f_t), mean over pairs",
       needs("DISTS", "DISTS_pytorch/weights.pt (alpha, beta) and torchvision vgg16-397923af.pth")},
      {"warp_loss", "Warp", false, "native (s4d::metrics::warp_error)", "", std::nullopt},
      {"dino_score", "Subject", true, "VBench subject consistency (DINO ViT-B/16)", "CLS cosine to previous and first frame",
       needs("DINO ViT-B/16", "dino_vitbase16_pretrain.pth")},
      {"ckdn", "CKDN", true, "pyiqa ckdn", "x = stylised frame, y = style image, 288x288 centre crop",
       needs("CKDN", "CKDN_model_best-38b27dc6.pth")},
      {"style_lpips", "Style LPIPS", false, "LPIPS v0.1 (frame vs style image resized to the frame)", "[0,1] -> [-1,1]",
       needs("LPIPS", "lpips v0.1 vgg.pth or alex.pth and torchvision vgg16-397923af.pth or alexnet-owt-7be5be79.pth")},
      {"content_ssim", "Content SSIM", true, "native (s4d::metrics::ssim)", "", std::nullopt},
      {"content_lpips", "Content LPIPS", false, "LPIPS v0.1 (stylised vs original frame)", "[0,1] -> [-1,1]",
       needs("LPIPS", "lpips v0.1 vgg.pth or alex.pth and torchvision vgg16-397923af.pth or alexnet-owt-7be5be79.pth")},
      {"style_loss_gram", "Gram loss", false, "VGG19 relu1_1..relu5_1 Gram, 1/(C H W)", "frame vs style image",
       needs("VGG19", "torchvision vgg19-dcbb9e9d.pth or AdaIN vgg_normalised.pth")},
      {"psnr", "PSNR", true, "native (s4d::metrics::psnr)", "", std::nullopt},
  };
}

}  // namespace

const std::vector<MetricEntry>& metric_catalog() {
  static const std::vector<MetricEntry> list = build();
  return list;
}

const MetricEntry& metric_entry(const std::string& key) {
  for (const auto& e : metric_catalog())
    if (e.key == key) return e;
  throw std::out_of_range("unknown metric key '" + key + "'");
}

}  // namespace s4d::bench
