// What shows the result of stages 3 and 4 (s4d/style_gaussians/stylize_run.h) and how temporally consistent it
// is, for `style4d stylize` and the demo. Adds to RUN/style/NAME/:
//   spiral/original, spiral/styled   spiral-path renders (frames.json) of the run and of the style,
//                                    with the original's exact flow
//   spiral/stylized_2d  the stage-3 stylizer run on the original spiral render (the 2D baseline)
//   contact_sheet.png   content, stage-3 frames and style renders of the test camera over time
//   stylize.json        the results (keys in docs/stylization.md)
// Built on the render protocols and the metrics, so it lives above training, which it measures.
#pragma once
#include <nlohmann/json.hpp>

#include "s4d/engine/context.h"
#include "s4d/style_gaussians/stylize_run.h"

namespace s4d::bench {

// Renders and measures a completed style (`out.complete`; std::invalid_argument otherwise), writes
// stylize.json and returns what it holds.
nlohmann::json measure_style(engine::Context& ctx, const style_gaussians::StylizeRequest& request, const style_gaussians::StylizeOutcome& out);

}  // namespace s4d::bench
