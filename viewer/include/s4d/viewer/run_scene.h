// A trained run as the viewer sees it: the Gaussians, the dataset's cameras, the background and
// the clip length. Today a run is the static stage (RUN/run.json, RUN/train.json,
// RUN/geometry/gaussians.ply); the 4D stage's files will be read here too.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"

namespace s4d::viewer {

struct RunScene {
  std::filesystem::path root;
  std::filesystem::path dataset;  // from run.json
  io::GaussianCloud cloud;
  // One view per physical camera of the dataset (its first frame; D-NeRF: every view), in dataset
  // order, named like the dataset ("cam03", "train/r_000").
  std::vector<io::CameraView> cameras;
  std::array<float, 3> background{};
  double clip_seconds = 1;  // playing t from 0 to 1 at speed 1 takes this long (frames at 30 fps)
  std::string stage;        // run.json "stage"
  double test_psnr = 0;     // train.json; 0 when not recorded
};

// Reads a run directory. Throws std::runtime_error saying everything that is missing at once
// (the directory, run.json, train.json, geometry/gaussians.ply, the dataset run.json names) and
// how to produce it, or naming the file that does not parse.
RunScene open_run(const std::filesystem::path& run_dir);

}  // namespace s4d::viewer
