#include "s4d/stylize/network_stylizer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/io/safetensors.h"
#include "s4d/stylize/image_file.h"

namespace s4d::stylize {

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

// Shorter side to `size` (0: unchanged), aspect kept.
io::ImageF resize_shorter_side(const io::ImageF& image, int size) {
  if (size <= 0 || std::min(image.width, image.height) == size) return image;
  const double scale = static_cast<double>(size) / std::min(image.width, image.height);
  return resize_image(image, std::max(1, static_cast<int>(std::lround(image.width * scale))),
                      std::max(1, static_cast<int>(std::lround(image.height * scale))));
}

std::filesystem::path weights_folder(const NetworkOptions& options, const std::string& stylizer, const char* files) {
  if (options.weights.empty())
    throw std::invalid_argument(stylizer + " needs weights: --weights DIR holding " + files +
                                " (the published .pth files converted, see README \"Network stylizers\")");
  if (!std::filesystem::is_directory(options.weights))
    throw std::invalid_argument("--weights " + options.weights.string() + " is not a folder (" + stylizer + " reads " +
                                files + " from it)");
  return options.weights;
}

}  // namespace

AdainStylizer::AdainStylizer(const NetworkOptions& options, const nn::VggWidths& widths)
    : ctx_(options.context), style_size_(options.style_size), widest_(widths.level[0]) {
  const auto dir = weights_folder(options, "adain", "vgg_normalised.safetensors and decoder.safetensors");
  if (ctx_ == nullptr) {
    owned_context_ = std::make_unique<engine::Context>();
    ctx_ = owned_context_.get();
  }
  net_ = std::make_unique<nn::AdainNet>(*ctx_, io::SafetensorsFile(dir / "vgg_normalised.safetensors"),
                                        io::SafetensorsFile(dir / "decoder.safetensors"), widths);
}

AdainStylizer::~AdainStylizer() = default;

std::vector<io::ImageF> AdainStylizer::stylize(const std::vector<io::ImageF>& frames, const io::ImageF& style_in,
                                               const StylizeSettings& settings, const FrameProgressFn& progress) const {
  check_inputs(frames, style_in, settings);
  if (settings.strength == 0.0f) return frames;
  const io::ImageF style = resize_shorter_side(style_in, style_size_);
  // The largest tensor: `widest_` channels at full size, rounded up to the pooling (decoder side).
  const uint64_t limit = ctx_->info().max_storage_buffer_range;
  for (const io::ImageF* image : {&frames[0], &style}) {
    const uint64_t bytes = uint64_t{widest_} * nn::pooled_size(image->height, 4) * 8 *
                           nn::pooled_size(image->width, 4) * 8 * sizeof(float);
    if (bytes > limit)
      throw std::invalid_argument("adain: a " + std::to_string(image->width) + "x" + std::to_string(image->height) +
                                  " " + (image == &style ? "style image" : "frame") + " needs " +
                                  std::to_string(bytes >> 20) + " MiB feature maps, over " + ctx_->info().name + "'s " +
                                  std::to_string(limit >> 20) + " MiB storage-buffer limit; use smaller frames" +
                                  (image == &style ? " or a smaller --style-size" : ""));
  }

  engine::Recorder style_rec(*ctx_, "adain style");
  const nn::Tensor style_tensor = nn::upload_tensor(*ctx_, "style", 3, style.height, style.width, to_chw(style));
  const engine::Buffer style_stats = net_->style_stats(style_rec, style_tensor);
  ctx_->run(std::move(style_rec));

  std::vector<io::ImageF> out;
  for (size_t t = 0; t < frames.size(); ++t) {
    const io::ImageF& frame = frames[t];
    engine::Recorder rec(*ctx_, "adain frame " + std::to_string(t));
    const nn::Tensor content = nn::upload_tensor(*ctx_, "content", 3, frame.height, frame.width, to_chw(frame));
    const nn::Tensor result = net_->stylize(rec, content, style_stats, settings.strength);
    ctx_->run(std::move(rec));
    const io::ImageF decoded =
        from_chw(nn::download(*ctx_, result), static_cast<int>(result.w), static_cast<int>(result.h));
    out.push_back(decoded.width == frame.width && decoded.height == frame.height
                      ? decoded
                      : resize_image(decoded, frame.width, frame.height));
    if (progress) progress(static_cast<int>(t) + 1, static_cast<int>(frames.size()));
  }
  return out;
}

}  // namespace s4d::stylize
