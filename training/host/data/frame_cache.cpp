#include "s4d/data/frame_cache.h"

#include "dataset_parts.h"
#include "video_decoders.h"

namespace s4d::data {
namespace {

// RGB of a 1-4 channel image, alpha composited on `background`.
io::ImageF to_rgb(const io::ImageF& in, const std::array<float, 3>& background) {
  io::ImageF out{in.width, in.height, 3, {}};
  const size_t pixels = static_cast<size_t>(in.width) * static_cast<size_t>(in.height);
  const size_t c = static_cast<size_t>(in.channels);
  const bool has_alpha = c == 2 || c == 4;
  const size_t colour_channels = has_alpha ? c - 1 : c;
  out.data.resize(3 * pixels);
  for (size_t p = 0; p < pixels; ++p) {
    const float* src = &in.data[p * c];
    const float a = has_alpha ? src[c - 1] : 1.0f;
    for (size_t k = 0; k < 3; ++k) {
      const float v = src[colour_channels == 1 ? 0 : k];
      out.data[3 * p + k] = v * a + background[k] * (1.0f - a);
    }
  }
  return out;
}

// Mean over factor x factor blocks; trailing rows and columns that fill no whole block are dropped.
io::ImageF box_downscale(const io::ImageF& in, int factor) {
  if (factor == 1) return in;
  const int w = detail::downscaled(in.width, factor), h = detail::downscaled(in.height, factor);
  io::ImageF out{w, h, in.channels, {}};
  const size_t c = static_cast<size_t>(in.channels);
  out.data.assign(static_cast<size_t>(w) * static_cast<size_t>(h) * c, 0.0f);
  const float weight = 1.0f / static_cast<float>(factor * factor);
  for (int y = 0; y < h * factor; ++y) {
    for (int x = 0; x < w * factor; ++x) {
      const float* src = &in.data[(static_cast<size_t>(y) * static_cast<size_t>(in.width) + static_cast<size_t>(x)) * c];
      float* dst = &out.data[(static_cast<size_t>(y / factor) * static_cast<size_t>(w) + static_cast<size_t>(x / factor)) * c];
      for (size_t k = 0; k < c; ++k) dst[k] += src[k] * weight;
    }
  }
  return out;
}

size_t byte_size(const io::ImageF& image) { return image.data.size() * sizeof(float); }

}  // namespace

FrameCache::FrameCache(const Dataset& dataset, size_t max_bytes)
    : downscale_(dataset.downscale),
      background_(dataset.background),
      max_bytes_(max_bytes),
      videos_(std::make_unique<detail::VideoDecoders>()) {}

FrameCache::~FrameCache() = default;
FrameCache::FrameCache(FrameCache&&) noexcept = default;
FrameCache& FrameCache::operator=(FrameCache&&) noexcept = default;

const io::ImageF& FrameCache::get(const View& view) {
  const bool video = view.frame_in_file >= 0;
  const std::string key = video ? view.image.string() + "#" + std::to_string(view.frame_in_file) : view.image.string();
  if (const auto it = index_.find(key); it != index_.end()) {
    entries_.splice(entries_.begin(), entries_, it->second);
    return entries_.front().image;
  }

  // Composite before filtering: the mean of composited pixels is the right colour, the composite of
  // mean colour and mean alpha is not.
  const io::ImageF decoded = video ? videos_->read(view.image, view.frame_in_file) : io::read_png(view.image);
  const int factor = view.file_downscale > 0 ? view.file_downscale : downscale_;
  io::ImageF image = box_downscale(to_rgb(decoded, background_), factor);
  if (image.width != view.camera.width || image.height != view.camera.height) {
    const std::string what = video ? "frame " + std::to_string(view.frame_in_file) : "image";
    detail::fail(view.image, what + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                 " after downscale " + std::to_string(factor) + ", but view '" + view.name +
                                 "' expects " + std::to_string(view.camera.width) + "x" +
                                 std::to_string(view.camera.height));
  }

  // Evict before inserting, but never the frame being returned: a budget below one frame still works,
  // holding just that frame.
  const size_t size = byte_size(image);
  while (!entries_.empty() && bytes_ + size > max_bytes_) {
    bytes_ -= byte_size(entries_.back().image);
    index_.erase(entries_.back().key);
    entries_.pop_back();
  }
  entries_.push_front(Entry{key, std::move(image)});
  index_[key] = entries_.begin();
  bytes_ += size;
  return entries_.front().image;
}

}  // namespace s4d::data
