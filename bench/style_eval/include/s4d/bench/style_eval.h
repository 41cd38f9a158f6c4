// Stages 3 and 4 (s4d/style_gaussians/stylize_run.h) and what shows their result and how temporally
// consistent it is, for `style4d stylize` and the demo. Adds to RUN/style/NAME/:
//   spiral/original, spiral/styled   spiral-path renders (frames.json) of the run and of the style,
//                                    with the original's exact flow
//   spiral/stylized_2d  the stage-3 stylizer run on the original spiral render (the 2D baseline)
//   contact_sheet.png   content, stage-3 frames and style renders of the test camera over time
//   stylize.json        the results (keys in docs/stylization.md); with a time budget, how it was spent
// Built on the render protocols and the metrics, so it lives above training, which it measures.
#pragma once
#include <atomic>

#include <nlohmann/json.hpp>

#include "s4d/engine/context.h"
#include "s4d/style_gaussians/stylize_run.h"

namespace s4d::bench {

struct StyleMeasured {
  style_gaussians::StylizeOutcome outcome;  // not complete: interrupted by `stop`, the checkpoint written
  nlohmann::json summary;                   // stylize.json's content; null when not complete
};

// Stage 3, the spiral's style-independent renders, stage 4, then the measurement, which writes
// stylize.json. With request.time_budget, stage 4 gets what is left of it once stage 3 and the
// style-independent renders took their time, less three quarters of that again for the measurement
// after stage 4 and train::kReserveShare for stage 4's closing test.
StyleMeasured stylize_and_measure(engine::Context& ctx, const style_gaussians::StylizeRequest& request,
                                  const std::atomic<bool>& stop);

}  // namespace s4d::bench
