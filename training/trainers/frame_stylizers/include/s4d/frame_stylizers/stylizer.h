// A frame stylizer: restyles one camera's frames (in time order) after a style image. The
// weight-free patch stylizer (patch_stylizer.h) is the default; network stylizers (AdaIN, MCCNet,
// ...) plug in behind the same interface.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::frame_stylizers {

struct StylizeSettings {
  // How far the result moves from the content: 0 returns the content, 1 the full stylization.
  float strength = 1.0f;
  uint64_t seed = 0;  // same seed, same inputs: same frames
};

// Called after each frame with (frames done, frames in all).
using FrameProgressFn = std::function<void(int done, int total)>;

class Stylizer {
 public:
  virtual ~Stylizer() = default;
  virtual std::string name() const = 0;

  // frames: RGB [H, W, 3] in [0, 1], all the same size, in time order (a stylizer may use the order
  // for temporal coherence). style: RGB [h, w, 3] of any size. Returns one RGB frame of the input's
  // size per input frame, values in [0, 1]. Throws std::invalid_argument for an empty sequence,
  // frames of mixed sizes or channel counts other than 3, or a strength outside [0, 1].
  virtual std::vector<io::ImageF> stylize(const std::vector<io::ImageF>& frames, const io::ImageF& style,
                                          const StylizeSettings& settings,
                                          const FrameProgressFn& progress = {}) const = 0;
};

// The checks every stylizer makes on its inputs (see Stylizer::stylize).
void check_inputs(const std::vector<io::ImageF>& frames, const io::ImageF& style, const StylizeSettings& settings);

}  // namespace s4d::frame_stylizers
