// The built-in scene in the D-NeRF layout with its monocular setting: one training image per time,
// each from another camera of the arc (the camera jumps between times, as D-NeRF's captures do),
// and the middle camera held out over every time as the test views.
//   DIR/train/r_NNN.png, DIR/test/r_NNN.png, DIR/transforms_{train,test}.json (camera_angle_x,
//   per frame file_path, time in [0, 1], transform_matrix = camera-to-world, OpenGL axes)
#pragma once
#include <filesystem>
#include <vector>

#include "s4d/synth/camera_rig.h"
#include "s4d/synth/dataset.h"
#include "s4d/synth/render.h"
#include "s4d/synth/scene.h"

namespace s4d::synth {

// The camera of training frame `frame` of `frames` among `cams` cameras, never camera 0 (the test
// camera): a fixed stride through cameras 1..cams-1, so consecutive times see from far-apart places.
int monocular_camera(int frame, int cams);

// Writes the images and transforms files into `dir`; cameras[0] is the test camera. Calls
// `progress` after each image, counting from `done`.
void write_dnerf_views(const std::filesystem::path& dir, const Scene& scene, const std::vector<PinholeCamera>& cameras,
                       const SynthOptions& options, const RenderSettings& settings, const ProgressFn& progress);

}  // namespace s4d::synth
