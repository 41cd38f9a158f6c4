// What the viewer takes from a run's dataset: the cameras to snap to and the clip's length.
#pragma once
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/io/nerf_cameras.h"

namespace s4d::viewer {

// One view per physical camera of the dataset (its first frame; D-NeRF: every view), in dataset
// order, named like the dataset ("cam03", "train/r_000"). scene::read_trained_run refuses datasets
// without views, so a run's list is never empty.
std::vector<io::CameraView> dataset_cameras(const data::Dataset& dataset);

// Seconds that playing t from 0 to 1 at speed 1 takes: the dataset's distinct times at 30 fps, at
// least 1.
double clip_seconds(const data::Dataset& dataset);

}  // namespace s4d::viewer
