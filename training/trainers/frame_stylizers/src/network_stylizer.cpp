#include "s4d/frame_stylizers/network_stylizer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "s4d/io/safetensors.h"
#include "s4d/nn/adaattn_net.h"
#include "s4d/nn/adain_net.h"
#include "s4d/nn/mcc_net.h"
#include "s4d/io/image_file.h"

namespace s4d::frame_stylizers {

namespace {

// RGB [H, W, 3] -> [3, H, W].
std::vector<float> to_chw(const io::ImageF& image) {
  const size_t plane = static_cast<size_t>(image.width) * image.height;
  std::vector<float> chw(3 * plane);
  for (size_t i = 0; i < plane; ++i)
    for (size_t c = 0; c < 3; ++c) chw[c * plane + i] = image.data[3 * i + c];
  return chw;
}

// [3, h, w] -> RGB [h, w, 3], clamped to [0, 1] as torchvision's save_image does.
io::ImageF from_chw(const std::vector<float>& chw, int width, int height) {
  const size_t plane = static_cast<size_t>(width) * height;
  io::ImageF image{width, height, 3, std::vector<float>(3 * plane)};
  for (size_t i = 0; i < plane; ++i)
    for (size_t c = 0; c < 3; ++c) image.data[3 * i + c] = std::clamp(chw[c * plane + i], 0.0f, 1.0f);
  return image;
}

// Shorter side to `size` (0: unchanged), aspect kept; then, with `square`, the centre square.
io::ImageF prepare_style(const io::ImageF& image, int size, bool square) {
  io::ImageF out = image;
  if (size > 0 && std::min(image.width, image.height) != size) {
    const double scale = static_cast<double>(size) / std::min(image.width, image.height);
    out = io::resize_image(image, std::max(size, static_cast<int>(std::lround(image.width * scale))),
                       std::max(size, static_cast<int>(std::lround(image.height * scale))));
  }
  if (!square || out.width == out.height) return out;
  const int side = std::min(out.width, out.height), x0 = (out.width - side) / 2, y0 = (out.height - side) / 2;
  io::ImageF crop{side, side, 3, std::vector<float>(static_cast<size_t>(side) * side * 3)};
  for (int y = 0; y < side; ++y)
    std::copy_n(&out.data[(static_cast<size_t>(y + y0) * out.width + x0) * 3], static_cast<size_t>(side) * 3,
                &crop.data[static_cast<size_t>(y) * side * 3]);
  return crop;
}

class NetworkStylizer final : public Stylizer {
 public:
  NetworkStylizer(std::string name, const NetworkOptions& options, const nn::VggWidths& widths)
      : name_(std::move(name)), ctx_(options.context), style_size_(options.style_size), widest_(widths.level[0]) {
    if (options.weights.empty())
      throw std::invalid_argument(name_ + " needs weights: --weights DIR holding " + files_text() +
                                  " (the published .pth files converted, see docs/stylization.md \"Network stylizers\")");
    if (!std::filesystem::is_directory(options.weights))
      throw std::invalid_argument("--weights " + options.weights.string() + " is not a folder (" + name_ + " reads " +
                                  files_text() + " from it)");
    if (ctx_ == nullptr) {
      owned_context_ = std::make_unique<engine::Context>();
      ctx_ = owned_context_.get();
    }
    const auto file = [&](const char* stem) {
      return io::SafetensorsFile(options.weights / (stem + std::string(".safetensors")));
    };
    if (name_ == "adain")
      net_ = std::make_unique<nn::AdainNet>(*ctx_, file("vgg_normalised"), file("decoder"), widths);
    else if (name_ == "adaattn")
      net_ = std::make_unique<nn::AdaattnNet>(*ctx_, file("vgg_normalised"), file("net_adaattn_3"),
                                              file("net_transformer"), file("net_decoder"), widths);
    else
      net_ = std::make_unique<nn::MccNet>(*ctx_, file("vgg_normalised"), file("decoder"), file("mcc_module"), widths);
  }

  std::string name() const override { return name_; }

  std::vector<io::ImageF> stylize(const std::vector<io::ImageF>& frames, const io::ImageF& style_image,
                                  const StylizeSettings& settings, const FrameProgressFn& progress) const override {
    check_inputs(frames, style_image, settings);
    if (settings.strength == 0.0f) return frames;
    const io::ImageF style = prepare_style(style_image, style_size_, name_ != "adain");
    check_size(frames[0], "frame");
    check_size(style, "style image");

    engine::Recorder style_rec(*ctx_, name_ + " style");
    const nn::Tensor style_tensor = nn::upload_tensor(*ctx_, "style", 3, style.height, style.width, to_chw(style));
    const nn::StyleCode style_code = net_->style(style_rec, style_tensor);
    ctx_->run(std::move(style_rec));

    std::vector<io::ImageF> out;
    for (size_t t = 0; t < frames.size(); ++t) {
      const io::ImageF& frame = frames[t];
      engine::Recorder rec(*ctx_, name_ + " frame " + std::to_string(t));
      const nn::Tensor content = nn::upload_tensor(*ctx_, "content", 3, frame.height, frame.width, to_chw(frame));
      const nn::Tensor result = net_->stylize(rec, content, style_code, settings.strength);
      ctx_->run(std::move(rec));
      io::ImageF decoded =
          from_chw(nn::download(*ctx_, result), static_cast<int>(result.w), static_cast<int>(result.h));
      const bool same_size = decoded.width == frame.width && decoded.height == frame.height;
      out.push_back(same_size ? std::move(decoded) : io::resize_image(decoded, frame.width, frame.height));
      if (progress) progress(static_cast<int>(t) + 1, static_cast<int>(frames.size()));
    }
    return out;
  }

 private:
  std::string files_text() const {
    const auto files = network_weight_files(name_);
    std::string s;
    for (size_t i = 0; i < files.size(); ++i) s += (i == 0 ? "" : i + 1 == files.size() ? " and " : ", ") + files[i];
    return s;
  }

  // One storage buffer holds a tensor; the largest is relu1_1-wide at the decoder's full size.
  void check_size(const io::ImageF& image, const std::string& what) const {
    const uint64_t limit = ctx_->info().max_storage_buffer_range;
    const uint64_t bytes =
        uint64_t{widest_} * nn::pooled_size(image.height, 4) * 8 * nn::pooled_size(image.width, 4) * 8 * sizeof(float);
    if (bytes <= limit) return;
    throw std::invalid_argument(name_ + ": a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " " + what + " needs " + std::to_string(bytes >> 20) + " MiB feature maps, over " +
                                ctx_->info().name + "'s " + std::to_string(limit >> 20) +
                                " MiB storage-buffer limit; use smaller frames" +
                                (what == "frame" ? "" : " or a smaller --style-size"));
  }

  std::string name_;
  std::unique_ptr<engine::Context> owned_context_;
  engine::Context* ctx_;
  int style_size_;
  uint32_t widest_;
  std::unique_ptr<nn::StyleNetwork> net_;  // after the context it runs on
};

}  // namespace

std::vector<std::string> network_stylizer_names() { return {"adain", "adaattn", "mccnet", "hgst"}; }

std::vector<std::string> network_weight_files(const std::string& name) {
  if (name == "adain") return {"vgg_normalised.safetensors", "decoder.safetensors"};
  if (name == "adaattn")
    return {"vgg_normalised.safetensors", "net_adaattn_3.safetensors", "net_transformer.safetensors",
            "net_decoder.safetensors"};
  return {"vgg_normalised.safetensors", "decoder.safetensors", "mcc_module.safetensors"};
}

std::unique_ptr<Stylizer> make_network_stylizer(const std::string& name, const NetworkOptions& options,
                                                const nn::VggWidths& widths) {
  const auto names = network_stylizer_names();
  if (std::find(names.begin(), names.end(), name) == names.end())
    throw std::invalid_argument("'" + name + "' is not a network stylizer");
  return std::make_unique<NetworkStylizer>(name, options, widths);
}

}  // namespace s4d::frame_stylizers
