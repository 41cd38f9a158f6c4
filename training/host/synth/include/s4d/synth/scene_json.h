// scene.json: a self-description of a synthetic dataset, so the files can be understood (and the
// scene rebuilt) without reading this code.
#pragma once
#include <string>
#include <vector>

#include "s4d/synth/camera_rig.h"
#include "s4d/synth/dataset.h"
#include "s4d/synth/scene.h"

namespace s4d::synth {

struct DepthBounds {
  double near = 0, far = 0;
};

std::string scene_json(const Scene& scene, const ArcRig& rig, const SynthOptions& options,
                       const std::vector<PinholeCamera>& cameras, const std::vector<DepthBounds>& bounds,
                       size_t num_points);

}  // namespace s4d::synth
