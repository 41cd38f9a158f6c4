#include "s4d/bench/native_learned.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "s4d/io/image_file.h"

namespace s4d::bench {

namespace fs = std::filesystem;

namespace {

constexpr const char* kVgg16 = "vgg16.safetensors";
constexpr const char* kLpipsVgg = "lpips_vgg.safetensors";
constexpr const char* kAlexnet = "alexnet.safetensors";
constexpr const char* kLpipsAlex = "lpips_alex.safetensors";
constexpr const char* kVggNormalised = "vgg_normalised.safetensors";
constexpr const char* kVgg19 = "vgg19.safetensors";
constexpr const char* kDists = "dists.safetensors";
constexpr const char* kDino = "dino_vitb16.safetensors";
constexpr const char* kCkdn = "ckdn.safetensors";
constexpr const char* kMusiq = "musiq.safetensors";
constexpr const char* kMusiqPaq2piq = "musiq_paq2piq.safetensors";
constexpr const char* kClipIqa = "clipiqa_plus.safetensors";

bool wanted(const std::vector<std::string>& keys, const char* key) {
  return keys.empty() || std::find(keys.begin(), keys.end(), key) != keys.end();
}

bool present(const NativeLearnedOptions& o, const std::string& file) {
  return o.weights_dir && fs::is_regular_file(*o.weights_dir / file);
}

bool all_present(const NativeLearnedOptions& o, const std::vector<std::string>& files) {
  return std::all_of(files.begin(), files.end(), [&](const std::string& f) { return present(o, f); });
}

std::string joined(const std::vector<std::string>& files) {
  std::string list;
  for (const std::string& f : files) list += (list.empty() ? "" : " and ") + f;
  return list;
}

// Why a key is unavailable: the files of `files` absent from the folder (those present said so), and
// `switch_hint` when the folder holds what another choice of network needs (e.g. "--lpips-net alex").
std::string missing(const NativeLearnedOptions& o, const std::vector<std::string>& files, const std::string& published,
                    const std::string& switch_hint = "") {
  std::string where = "pass --metric-weights DIR holding " + joined(files);
  if (o.weights_dir) {
    std::vector<std::string> absent, there;
    for (const std::string& f : files) (present(o, f) ? there : absent).push_back(f);
    where = "add " + joined(absent) + " to " + o.weights_dir->string() + " (--metric-weights" +
            (there.empty() ? "" : "; " + joined(there) + (there.size() == 1 ? " is" : " are") + " there") + ")";
  }
  return "needs weights: " + where + ", converted from " + published +
         " by tools/convert_weights.py (docs/bench.md, \"Learned metrics\")" + switch_hint +
         ", or pass --python PY for the pyiqa bridge";
}

}  // namespace

const std::vector<std::string>& native_learned_keys() {
  static const std::vector<std::string> keys = {"dists", "style_lpips", "content_lpips", "style_loss_gram",
                                                   "dino_score", "ckdn", "clipiqa_plus", "musiq", "musiq_paq2piq"};
  return keys;
}

NativeLearned::NativeLearned(engine::Context& ctx, const NativeLearnedOptions& options) : options_(options) {
  if (options.weights_dir && !fs::is_directory(*options.weights_dir))
    throw std::invalid_argument("--metric-weights " + options.weights_dir->string() + ": not a folder");
  const bool vgg = options.lpips == metrics::LpipsNet::vgg;
  const std::vector<std::string> lpips_files = {vgg ? kVgg16 : kAlexnet, vgg ? kLpipsVgg : kLpipsAlex};
  const std::vector<std::string> dists_files = {kVgg16, kDists};
  // vgg16.safetensors (59 MB from tools/convert_weights.py, 528 MB if the classifier was kept) is read
  // once for LPIPS and DISTS.
  std::optional<io::SafetensorsFile> vgg16;
  if ((vgg && all_present(options, lpips_files)) || all_present(options, dists_files))
    vgg16.emplace(*options.weights_dir / kVgg16);
  if (all_present(options, lpips_files)) {
    const io::SafetensorsFile heads(*options.weights_dir / lpips_files[1]);
    if (vgg)
      lpips_ = std::make_unique<metrics::Lpips>(ctx, *vgg16, heads, options.lpips, std::nullopt, options.lpips_input);
    else
      lpips_ = std::make_unique<metrics::Lpips>(ctx, io::SafetensorsFile(*options.weights_dir / kAlexnet), heads, options.lpips,
                                                std::nullopt, options.lpips_input);
  } else {
    const std::vector<std::string> other = {vgg ? kAlexnet : kVgg16, vgg ? kLpipsAlex : kLpipsVgg};
    const std::string hint = all_present(options, other) ? std::string(", or pass --lpips-net ") + (vgg ? "alex" : "vgg") +
                                                               " to use the " + joined(other) + " there"
                                                         : "";
    const std::string why = missing(options, lpips_files,
                                    vgg ? "torchvision vgg16-397923af.pth and LPIPS weights/v0.1/vgg.pth"
                                        : "torchvision alexnet-owt-7be5be79.pth and LPIPS weights/v0.1/alex.pth",
                                    hint);
    unavailable_["content_lpips"] = unavailable_["style_lpips"] = why;
  }
  if (all_present(options, dists_files))
    dists_ = std::make_unique<metrics::Dists>(ctx, *vgg16, io::SafetensorsFile(*options.weights_dir / kDists));
  else
    unavailable_["dists"] = missing(options, dists_files, "torchvision vgg16-397923af.pth and DISTS_pytorch/weights.pt");
  const bool normalised = options.gram == metrics::GramBackbone::vgg_normalised;
  const std::string gram_file = normalised ? kVggNormalised : kVgg19;
  if (all_present(options, {gram_file}))
    gram_ = std::make_unique<metrics::GramStyleLoss>(ctx, io::SafetensorsFile(*options.weights_dir / gram_file), options.gram);
  else
    unavailable_["style_loss_gram"] =
        missing(options, {gram_file}, normalised ? "AdaIN's vgg_normalised.pth" : "torchvision vgg19-dcbb9e9d.pth",
                present(options, normalised ? kVgg19 : kVggNormalised)
                    ? std::string(", or pass --gram-vgg ") + (normalised ? "torchvision to use the vgg19.safetensors there"
                                                                         : "normalised to use the vgg_normalised.safetensors there")
                    : "");
  if (all_present(options, {kDino}))
    dino_ = std::make_unique<metrics::DinoSubject>(ctx, io::SafetensorsFile(*options.weights_dir / kDino));
  else
    unavailable_["dino_score"] = missing(options, {kDino}, "DINO's dino_vitbase16_pretrain.pth");
  if (all_present(options, {kCkdn}))
    ckdn_ = std::make_unique<metrics::Ckdn>(ctx, io::SafetensorsFile(*options.weights_dir / kCkdn));
  else
    unavailable_["ckdn"] = missing(options, {kCkdn}, "pyiqa's CKDN_model_best-38b27dc6.pth");
  if (all_present(options, {kClipIqa}))
    clipiqa_ = std::make_unique<metrics::ClipIqaPlus>(ctx, io::SafetensorsFile(*options.weights_dir / kClipIqa));
  else
    unavailable_["clipiqa_plus"] =
        missing(options, {kClipIqa}, "OpenAI CLIP's RN50.pt and pyiqa's CLIP-IQA+_learned_prompts-603f3273.pth");
  if (all_present(options, {kMusiq}))
    musiq_ = std::make_unique<metrics::Musiq>(ctx, io::SafetensorsFile(*options.weights_dir / kMusiq));
  else
    unavailable_["musiq"] = missing(options, {kMusiq}, "pyiqa's musiq_koniq_ckpt-e95806b9.pth");
  if (all_present(options, {kMusiqPaq2piq}))
    musiq_paq2piq_ = std::make_unique<metrics::Musiq>(ctx, io::SafetensorsFile(*options.weights_dir / kMusiqPaq2piq));
  else
    unavailable_["musiq_paq2piq"] = missing(options, {kMusiqPaq2piq}, "pyiqa's musiq_paq2piq_ckpt-364c0c84.pth");
}

bool NativeLearned::computes(const std::string& key) const {
  return std::find(native_learned_keys().begin(), native_learned_keys().end(), key) != native_learned_keys().end() &&
         unavailable_.count(key) == 0;
}

std::string NativeLearned::impl(const std::string& key) const {
  if (key == "dino_score") {
    const nn::VitShape& s = dino_->shape();
    return "native DINO ViT (dino_vitb16.safetensors: width " + std::to_string(s.width) + ", " + std::to_string(s.depth) +
           " blocks, " + std::to_string(s.heads) + " heads, patch " + std::to_string(s.patch) + ") on the GPU";
  }
  if (key == "clipiqa_plus") {
    const nn::ClipResnet& n = clipiqa_->net();
    return "native CLIP-IQA+, CLIP ResNet (clipiqa_plus.safetensors: width " + std::to_string(n.width()) + ", blocks " +
           std::to_string(n.blocks()[0]) + "-" + std::to_string(n.blocks()[1]) + "-" + std::to_string(n.blocks()[2]) + "-" +
           std::to_string(n.blocks()[3]) + ", " + std::to_string(n.heads()) + " heads, " + std::to_string(n.output_dim()) +
           "-d) + stored prompt features, on the GPU";
  }
  if (key == "ckdn") return "native CKDN, two ResNet-50 stems + layer2 + MLP (ckdn.safetensors) on the GPU";
  if (key == "musiq" || key == "musiq_paq2piq") {
    const nn::MusiqShape& s = (key == "musiq" ? musiq_ : musiq_paq2piq_)->shape();
    return "native MUSIQ (" + std::string(key == "musiq" ? kMusiq : kMusiqPaq2piq) + ": ResNet root per 32x32 patch, width " +
           std::to_string(s.width) + ", " + std::to_string(s.depth) + " blocks, " + std::to_string(s.heads) + " heads) on the GPU";
  }
  if (key == "dists") return "native DISTS, VGG16 with L2 pooling (vgg16.safetensors + dists.safetensors) on the GPU";
  if (key == "style_loss_gram")
    return std::string("native VGG19 (") +
           (options_.gram == metrics::GramBackbone::vgg_normalised ? kVggNormalised : kVgg19) + ") on the GPU";
  return options_.lpips == metrics::LpipsNet::vgg
             ? "native LPIPS v0.1 VGG16 (vgg16.safetensors + lpips_vgg.safetensors) on the GPU"
             : "native LPIPS v0.1 AlexNet (alexnet.safetensors + lpips_alex.safetensors) on the GPU";
}

std::string NativeLearned::convention(const std::string& key) const {
  if (key == "clipiqa_plus")
    return "pyiqa clipiqa+ (RN50): RGB [0,1] at full resolution, no resize, OpenAI CLIP mean/std, no position embedding "
           "(pos_embedding=False), softmax(exp(logit_scale) cos(image, [good, bad] prompt features)) of the good prompt; "
           "mean over frames";
  if (key == "ckdn")
    return "pyiqa ckdn(x = stylised frame, y = style image): RGB [0,1], shorter side to 329 (x bicubic antialiased, y "
           "nearest), 288x288 centre crop, ImageNet mean/std, sigmoid of the MLP on the global average of "
           "layer2(stem_x(x) - stem_y(y)); mean over frames";
  if (key == "musiq" || key == "musiq_paq2piq")
    return "pyiqa MUSIQ of each stylised frame: RGB [0,1] -> 2x-1, scales of longer side 224 and 384 (bicubic, no "
           "antialiasing) and the full frame, 32x32 patches with TF SAME zero padding, hashed 10x10 positions, padded "
           "tokens left out (masked to exactly 0 weight in pyiqa); mean over frames";
  if (key == "dists")
    return "DISTS(f_t+1, f_t) of consecutive stylised frames: RGB [0,1], no resize (pyiqa), stage 0 the raw input, "
           "VGG16 relu1_2..relu5_3 of the ImageNet-normalised input with L2 pooling, global per-channel statistics, "
           "c1 = c2 = 1e-6; mean over pairs";
  if (key == "dino_score")
    return "VBench subject consistency: dino_transform(224) (uint8 frame, shorter side 224 bilinear without antialiasing, "
           "rounded to uint8, ImageNet mean/std, no crop), L2-normalised class token f_i, s_i = (max(0, cos(f_i-1, f_i)) + "
           "max(0, cos(f_0, f_i))) / 2 for i >= 1";
  if (key == "style_loss_gram")
    return std::string("relu1_1..relu5_1 Gram matrices F F^T / (C H W), sum over layers of the mean squared "
                       "difference, frame vs the style image at its own size; ") +
           (options_.gram == metrics::GramBackbone::vgg_normalised
                ? "AdaIN vgg_normalised (raw [0,1] RGB, reflection padding, ceil-mode pooling)"
                : "torchvision vgg19 (ImageNet mean/std, zero padding)") +
           "; mean over frames";
  const std::string lpips = std::string(options_.lpips_input == metrics::LpipsInput::signed_unit
                                            ? "RGB [0,1] -> 2x-1 -> scaling layer, "
                                            : "RGB [0,1] as is (3DGS lpipsPyTorch, no 2x-1) -> scaling layer, ") +
                            (options_.lpips == metrics::LpipsNet::vgg ? "VGG16 relu1_2..relu5_3" : "AlexNet relu1..relu5") +
                            ", channel unit-normalisation (eps 1e-10), lin heads, spatial mean, sum over layers; ";
  if (key == "style_lpips")
    return lpips + "frame vs the style image resized to the frame (area when shrinking, bilinear when enlarging); mean over frames";
  return lpips + "stylised vs original frame; mean over frames";
}

void NativeLearned::score_frame(const io::ImageF& stylised, const io::ImageF& original, const fs::path& style_image,
                                bool follows, const std::vector<std::string>& keys,
                                std::map<std::string, std::vector<double>>& per_frame) const {
  if (!style_image.empty() && style_image != style_path_) {
    style_ = io::read_image_rgb(style_image);
    style_path_ = style_image;
    style_lpips_.clear();
    style_gram_.reset();
  }
  const bool content = lpips_ && wanted(keys, "content_lpips");
  const bool style = lpips_ && !style_image.empty() && wanted(keys, "style_lpips");
  if (content || style) {
    const metrics::LpipsFeatures frame = lpips_->features(stylised);
    if (content) per_frame["content_lpips"].push_back(lpips_->distance(frame, lpips_->features(original)));
    if (style) {
      const std::pair<int, int> size{stylised.width, stylised.height};
      auto it = style_lpips_.find(size);
      if (it == style_lpips_.end())
        it = style_lpips_.emplace(size, lpips_->features(io::resize_image(style_, size.first, size.second))).first;
      per_frame["style_lpips"].push_back(lpips_->distance(frame, it->second));
    }
  }
  if (gram_ && !style_image.empty() && wanted(keys, "style_loss_gram")) {
    if (!style_gram_) style_gram_ = gram_->grams(style_);
    per_frame["style_loss_gram"].push_back(metrics::gram_loss(gram_->grams(stylised), *style_gram_));
  }
  if (clipiqa_ && wanted(keys, "clipiqa_plus")) per_frame["clipiqa_plus"].push_back((*clipiqa_)(stylised));
  if (ckdn_ && !style_image.empty() && wanted(keys, "ckdn")) per_frame["ckdn"].push_back((*ckdn_)(stylised, style_));
  if (musiq_ && wanted(keys, "musiq")) per_frame["musiq"].push_back((*musiq_)(stylised));
  if (musiq_paq2piq_ && wanted(keys, "musiq_paq2piq")) per_frame["musiq_paq2piq"].push_back((*musiq_paq2piq_)(stylised));
  if (dists_ && wanted(keys, "dists")) {
    metrics::DistsFeatures current = dists_->features(stylised);
    if (follows && previous_) per_frame["dists"].push_back(dists_->distance(current, *previous_));
    previous_ = std::move(current);
  }
  if (dino_ && wanted(keys, "dino_score")) {
    std::vector<double> current = dino_->features(stylised);
    if (!follows || !dino_first_) dino_first_ = current;
    else per_frame["dino_score"].push_back(metrics::subject_pair_score(*dino_first_, dino_previous_, current));
    dino_previous_ = std::move(current);
  }
}

}  // namespace s4d::bench
