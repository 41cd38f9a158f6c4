// Lazily loaded training frames with a byte budget, so that e.g. 300 frames x 20 cameras never all
// sit in memory: least-recently-used frames are dropped and re-read from disk when needed again.
#pragma once
#include <array>
#include <cstddef>
#include <list>
#include <string>
#include <unordered_map>

#include "s4d/data/dataset.h"
#include "s4d/io/image_io.h"

namespace s4d::data {

class FrameCache {
 public:
  // Takes the dataset's downscale factor and background; the dataset itself need not outlive the cache.
  FrameCache(const Dataset& dataset, size_t max_bytes);

  // The view's image as RGB float [H, W, 3], alpha composited on the background (rgb a + bg (1 - a)),
  // box-filtered by the downscale factor. The reference stays valid until the next get(). Throws
  // std::runtime_error naming the file when it is missing, unreadable, or not the view's camera size.
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
};

}  // namespace s4d::data
