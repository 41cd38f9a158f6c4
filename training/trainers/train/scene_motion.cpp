#include "s4d/train/scene_motion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <vector>

#include "s4d/train/data_recipe.h"

namespace s4d::train {

namespace {

double changed_share(const io::ImageF& a, const io::ImageF& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) return 1.0;  // not one camera's frames
  size_t changed = 0;
  const size_t pixels = size_t(a.width) * a.height, c = a.channels;
  for (size_t p = 0; p < pixels; ++p)
    for (size_t k = 0; k < c; ++k)
      if (std::fabs(a.data[p * c + k] - b.data[p * c + k]) > kPixelChange) {
        ++changed;
        break;
      }
  return pixels == 0 ? 0.0 : double(changed) / double(pixels);
}

}  // namespace

nlohmann::json MotionCheck::to_json() const {
  return {{"motion", motion == Motion::still ? "still" : motion == Motion::moving ? "moving" : "unknown"},
          {"changed_share", changed_share}, {"cameras", cameras}, {"comparisons", comparisons}, {"why", why}};
}

MotionCheck check_motion(const data::Dataset& dataset, data::FrameCache& frames) {
  MotionCheck m;
  if (capture_kind(dataset) == "monocular") {
    m.why = "monocular capture: its frames differ by viewpoint as well as by motion, so they cannot tell";
    return m;
  }
  std::map<int, std::vector<const data::View*>> by_camera;  // each camera's views in time order
  for (const data::View& v : dataset.views)
    if (v.camera_index >= 0) by_camera[v.camera_index].push_back(&v);
  for (auto& [camera, views] : by_camera) {
    std::sort(views.begin(), views.end(), [](const data::View* a, const data::View* b) { return a->time < b->time; });
    if (views.size() < 2) continue;
    ++m.cameras;
    const io::ImageF first = frames.get(*views.front());  // a copy: get() reuses its reference
    for (uint32_t k = 1; k < kMotionSamples; ++k) {
      const size_t i = (views.size() - 1) * k / (kMotionSamples - 1);
      if (i == 0) continue;
      m.changed_share = std::max(m.changed_share, changed_share(first, frames.get(*views[i])));
      ++m.comparisons;
    }
  }
  char line[200];
  if (m.comparisons == 0) {
    m.why = "no camera has frames at two times";
    m.motion = Motion::still;
    return m;
  }
  m.motion = m.changed_share > kMovingShare ? Motion::moving : Motion::still;
  std::snprintf(line, sizeof line, "%s: up to %.3g %% of a camera's pixels change (over %u cameras, %u frame pairs; motion above %.3g %%)",
                m.motion == Motion::moving ? "the frames show motion" : "the frames show no motion", 100 * m.changed_share,
                m.cameras, m.comparisons, 100 * kMovingShare);
  m.why = line;
  return m;
}

nlohmann::json skip_field_if_still(run::TrainConfig& config, const data::Dataset& dataset, data::FrameCache& frames) {
  const MotionCheck motion = check_motion(dataset, frames);
  nlohmann::json decision = motion.to_json();
  if (motion.motion != Motion::still) {
    decision["trained"] = "yes";
  } else if (config.fine_iterations_given) {
    decision["trained"] = "yes: --fine-iters asked for it";
  } else {
    // Its steps go to the static stage, which then trains the Gaussians as long as both stages would.
    run::set_iterations(config, config.iterations + config.fine_iterations);
    config.fine_iterations = 0;
    decision["trained"] = "no: the 4DGS stage is skipped and its steps go to the static stage (--fine-iters N trains it anyway)";
    std::cerr << "no deformation field: " << motion.why << "; the 4DGS stage is skipped and its steps go to the static stage, "
              << config.iterations << " steps (--fine-iters N trains it anyway)\n";
  }
  return decision;
}

}  // namespace s4d::train
