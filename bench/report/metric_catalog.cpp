#include "s4d/bench/metric_catalog.h"

#include <stdexcept>

namespace s4d::bench {

namespace {

// The learned metrics when this call computes them neither natively nor through the pyiqa bridge:
// what to supply. `native_files` names the --metric-weights files (docs/bench.md, "Learned metrics"); empty
// for metrics only the bridge computes.
std::string needs(const std::string& native_files, const std::string& published) {
  const std::string bridge = "pass --python PY, a Python with pyiqa, to compute it through the pyiqa bridge";
  if (native_files.empty()) return "needs " + published + ": " + bridge + " (no native implementation)";
  return "needs weights: pass --metric-weights DIR holding " + native_files + " (converted from " + published +
         " by tools/convert_weights.py; docs/bench.md, \"Learned metrics\"), or " + bridge;
}

std::vector<MetricEntry> build() {
  return {
      {"uiqm", "UIQM", true, "native (s4d::metrics::uiqm)", "", std::nullopt},
      {"clipiqa_plus", "CLIP-IQA+", true, "pyiqa clipiqa+ (RN50)", "[0,1] RGB, no resize, CLIP mean/std",
       needs("clipiqa_plus.safetensors", "OpenAI CLIP's RN50.pt and pyiqa's CLIP-IQA+_learned_prompts-603f3273.pth")},
      {"musiq", "MUSIQ", true, "pyiqa musiq (KonIQ)", "multi-scale 224/384 + full resolution",
       needs("musiq.safetensors", "pyiqa's musiq_koniq_ckpt-e95806b9.pth")},
      {"qalign", "Q-Align", true, "pyiqa qalign, task aesthetic", "q-future/one-align (8B parameters)",
       needs("", "q-future/one-align (about 16 GB)")},
      {"musiq_paq2piq", "MUSIQ-PaQ2PiQ", true, "pyiqa musiq-paq2piq", "multi-scale 224/384 + full resolution",
       needs("musiq_paq2piq.safetensors", "pyiqa's musiq_paq2piq_ckpt-364c0c84.pth")},
      {"dists", "DISTS", false, "DISTS (VGG16 + alpha/beta)", "consecutive frames DISTS(f_t+1, f_t), mean over pairs",
       needs("vgg16.safetensors and dists.safetensors", "torchvision vgg16-397923af.pth and DISTS_pytorch/weights.pt")},
      {"warp_loss", "Warp", false, "native (s4d::metrics::warp_error)", "", std::nullopt},
      {"dino_score", "Subject", true, "VBench subject consistency (DINO ViT-B/16)", "CLS cosine to previous and first frame",
       needs("dino_vitb16.safetensors", "DINO's ViT-B/16 dino_vitbase16_pretrain.pth")},
      {"ckdn", "CKDN", true, "pyiqa ckdn", "x = stylised frame, y = style image, 288x288 centre crop",
       needs("ckdn.safetensors", "pyiqa's CKDN_model_best-38b27dc6.pth")},
      {"style_lpips", "Style LPIPS", false, "LPIPS v0.1 VGG or AlexNet (frame vs style image resized to the frame)", "[0,1] -> [-1,1]",
       needs("vgg16.safetensors and lpips_vgg.safetensors (or alexnet.safetensors and lpips_alex.safetensors with --lpips-net alex)",
             "torchvision vgg16-397923af.pth / alexnet-owt-7be5be79.pth and LPIPS v0.1 weights/v0.1/vgg.pth / alex.pth")},
      {"content_ssim", "Content SSIM", true, "native (s4d::metrics::ssim)", "", std::nullopt},
      {"content_lpips", "Content LPIPS", false, "LPIPS v0.1 VGG or AlexNet (stylised vs original frame)", "[0,1] -> [-1,1]",
       needs("vgg16.safetensors and lpips_vgg.safetensors (or alexnet.safetensors and lpips_alex.safetensors with --lpips-net alex)",
             "torchvision vgg16-397923af.pth / alexnet-owt-7be5be79.pth and LPIPS v0.1 weights/v0.1/vgg.pth / alex.pth")},
      {"style_loss_gram", "Gram loss", false, "VGG19 relu1_1..relu5_1 Gram, 1/(C H W)", "frame vs style image",
       needs("vgg_normalised.safetensors (or vgg19.safetensors with --gram-vgg torchvision)",
             "AdaIN's vgg_normalised.pth or torchvision vgg19-dcbb9e9d.pth")},
      // The label reports have carried since before PSNR moved to s4d/io/psnr.h (same computation);
      // `bench --merge` compares impl labels, so a new one would refuse to merge older reports.
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
