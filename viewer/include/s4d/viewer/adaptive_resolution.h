// The render scale of the viewer while the view changes (camera moving, time playing, style or
// blend changing), as splat viewers do: render fewer pixels while moving so the frame rate holds,
// then refine to full resolution when the view is still. Pure logic on measured times; no device.
//
// Model: a frame's render time grows with its pixel count, scale^2. After each rendered frame the
// policy predicts the time of its current moving scale from the measurement; when the prediction
// leaves the band [kLowFraction, 1] x budget it moves the scale so the prediction lands on
// kTargetFraction x budget, rounded to steps of 1/kSteps and clamped to [floor, 1]. Inside the
// band it keeps the scale (the hysteresis that keeps it from oscillating between two steps).
// The full-resolution refine waits until the view has been still for settle_ms, so a pause of a
// frame or two inside a drag (a frame with no mouse motion) does not cost a full-resolution render.
// Fixed costs (projection, sorting) do not shrink with the scale, so the model is optimistic
// going down and pessimistic going up; the band lets the next measurements correct it.
#pragma once
#include <cstdint>

namespace s4d::viewer {

struct AdaptiveResolutionOptions {
  double budget_ms = 100;  // frame-time budget while moving (100 ms = 10 fps); 0: always full resolution
  double floor = 0.25;     // the lowest scale of each side
  double settle_ms = 150;  // how long the view stays still before the full-resolution refine
};

class AdaptiveResolution {
 public:
  static constexpr double kTargetFraction = 0.8;  // aim a little under the budget
  static constexpr double kLowFraction = 0.5;     // below half the budget, raise the scale
  static constexpr int kSteps = 16;               // scales are multiples of 1/16

  // Throws std::invalid_argument naming the field for a negative budget or settle time, or a floor
  // outside (0, 1].
  explicit AdaptiveResolution(AdaptiveResolutionOptions options = {});

  // The scale to render the next frame at: the moving scale while the view changes, 1 when it is
  // still or the budget is 0.
  double scale(bool moving) const { return moving ? moving_scale_ : 1.0; }
  double moving_scale() const { return moving_scale_; }
  // Whether a view still for `still_ms` (since its last change) should be refined to full resolution.
  bool refine(double still_ms) const { return still_ms >= options_.settle_ms; }
  // A frame rendered at `scale` took `ms`; updates the moving scale.
  void measured(double ms, double scale);

 private:
  AdaptiveResolutionOptions options_;
  double moving_scale_ = 1;
};

// The render size of one side at `scale`: round(size * scale), at least 1.
uint32_t scaled_size(uint32_t size, double scale);

}  // namespace s4d::viewer
