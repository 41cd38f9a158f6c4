#include "s4d/train/data_recipe.h"

#include <map>

namespace s4d::train {

namespace {
constexpr double kMonocularViewsPerTime = 1.5;  // a monocular capture has 1; the smallest rig 2
}

data::LoadOptions load_options(const run::TrainConfig& c, bool resumed) {
  data::LoadOptions o{.downscale = c.downscale};
  if (!c.frames.empty()) o.frames = data::parse_frame_range(c.frames, "frames");
  if (resumed || c.background_given) o.background = c.background;
  return o;
}

double train_views_per_time(const data::Dataset& dataset) {
  std::map<double, size_t> per_time;
  for (const data::View& v : dataset.views) {
    if (!v.test) ++per_time[v.time];
  }
  size_t views = 0;
  for (const auto& [time, count] : per_time) views += count;
  return per_time.empty() ? 0.0 : static_cast<double>(views) / static_cast<double>(per_time.size());
}

std::string capture_kind(const data::Dataset& dataset) {
  return train_views_per_time(dataset) <= kMonocularViewsPerTime ? "monocular" : "multi-view";
}

nlohmann::json adapt_to_data(run::TrainConfig& config, const data::Dataset& dataset) {
  const std::string capture = capture_kind(dataset);
  nlohmann::json choices = {{"capture", capture}, {"views_per_time", train_views_per_time(dataset)}};
  if (config.static_max_time < 0) {
    // The first frame as the canonical scene lets large motions survive on a rig, where it is seen by
    // every camera; a monocular capture has one view per moment, and a static stage on one view
    // fits a picture, not a scene (D-NeRF lego: 9.6 dB static, 14.4 dB after 4DGS), so it sees every
    // frame there, as 4DGaussians' coarse stage does.
    const bool monocular = capture == "monocular";
    config.static_max_time = monocular ? 1.0 : 0.0;
    choices["static_max_time"] = {
        {"value", config.static_max_time},
        {"why", monocular ? "monocular capture: the static stage sees every frame (4DGaussians' coarse stage)"
                          : "multi-view capture: the first frame, seen by every camera, is the canonical scene"}};
  } else {
    choices["static_max_time"] = {{"value", config.static_max_time}, {"why", "set explicitly"}};
  }
  return choices;
}

}  // namespace s4d::train
