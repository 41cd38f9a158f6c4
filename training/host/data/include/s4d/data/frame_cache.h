// Lazily loaded training frames with a byte budget, so that e.g. 300 frames x 20 cameras never all
// sit in memory: least-recently-used frames are dropped and re-read from disk when needed again.
// Video frames are decoded on demand from one open decoder per video, in order without seeking when
// the views are asked for in frame order.
#pragma once
#include <array>
#include <cstddef>
#include <list>
#include <memory>
#include <string>
#include <unordered_map>

#include "s4d/data/dataset.h"
#include "s4d/io/image_io.h"

namespace s4d::data {

namespace detail {
class VideoDecoders;
}

class FrameCache {
 public:
  // Takes the dataset's downscale factor and background; the dataset itself need not outlive the cache.
  FrameCache(const Dataset& dataset, size_t max_bytes);
  ~FrameCache();
  FrameCache(FrameCache&&) noexcept;
  FrameCache& operator=(FrameCache&&) noexcept;

  // The view's image as RGB float [H, W, 3], alpha composited on the background (rgb a + bg (1 - a)),
  // box-filtered by the downscale factor. The reference stays valid until the next get(). Throws
  // std::runtime_error naming the file when it is missing, unreadable, or not the view's camera size,
  // or (videos) when the view's frame cannot be decoded.
  // Not thread-safe.
  const io::ImageF& get(const View& view);

  size_t bytes() const { return bytes_; }          // held now; <= max_bytes, or one frame if larger
  size_t frames() const { return entries_.size(); }

 private:
  struct Entry {
    std::string key;
    io::ImageF image;
  };

  int downscale_;
  std::array<float, 3> background_;
  size_t max_bytes_;
  size_t bytes_ = 0;
  std::list<Entry> entries_;  // most recently used first
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
  std::unique_ptr<detail::VideoDecoders> videos_;
};

}  // namespace s4d::data
