#include "s4d/frame_stylizers/stylizer.h"

#include <stdexcept>
#include <string>

namespace s4d::frame_stylizers {

namespace {

bool rgb_of_size(const io::ImageF& image) {
  return image.channels == 3 && image.width > 0 && image.height > 0 &&
         image.data.size() == static_cast<size_t>(image.width) * image.height * 3;
}

}  // namespace

void check_inputs(const std::vector<io::ImageF>& frames, const io::ImageF& style, const StylizeSettings& settings) {
  if (frames.empty()) throw std::invalid_argument("stylize: no frames");
  if (!rgb_of_size(style)) throw std::invalid_argument("stylize: the style image is not a non-empty RGB image");
  for (size_t t = 0; t < frames.size(); ++t)
    if (!rgb_of_size(frames[t]) || frames[t].width != frames[0].width || frames[t].height != frames[0].height)
      throw std::invalid_argument("stylize: frame " + std::to_string(t) + " is not an RGB image of frame 0's size (" +
                                  std::to_string(frames[0].width) + "x" + std::to_string(frames[0].height) + ")");
  if (!(settings.strength >= 0.0f && settings.strength <= 1.0f))
    throw std::invalid_argument("stylize: strength " + std::to_string(settings.strength) + " is outside [0, 1]");
}

}  // namespace s4d::frame_stylizers
