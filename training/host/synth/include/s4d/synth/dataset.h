// `style4d synth`'s dataset writer: renders every camera and frame of the built-in scene and
// writes it in the DyNeRF / Neu3D layout,
//   DIR/camNN/NNNN.png   RGB 8-bit, camera NN (from 00), frame NNNN (from 0000), t = frame / (frames - 1);
//                        cam00 is the arc's middle camera (Neu3D's held-out centre view), then left to right
//   DIR/camNN.mp4        instead, with `video`: all frames of camera NN as MPEG-4 Part 2 (mp4v) at
//                        30 fps; lossy (see s4d/data/video_writer.h)
//   DIR/poses_bounds.npy float64 [cams, 17]: LLFF 3x5 (down, right, back | centre | H, W, focal), near, far
//   DIR/points3D.ply     coloured surface points at t = 0 for Gaussian initialisation
//   DIR/scene.json       the scene, the parameters, the intrinsics and the conventions
// Everything is written into DIR.partial and renamed to DIR at the end, so an interrupted run
// never leaves something that looks like a finished dataset.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

namespace s4d::synth {

struct SynthOptions {
  int cams = 10, frames = 30, width = 160, height = 120;
  uint64_t seed = 0;
  int samples_per_axis = 2;
  int points = 4000;
  bool video = false;  // camNN.mp4 videos instead of camNN/ frame folders; needs even width and height
  bool dnerf = false;  // the D-NeRF layout, monocular: one training camera per time (dnerf_layout.h)
  // The moving objects alone on black, cameras on a full ring above them looking down: an object
  // capture like D-NeRF's (with `dnerf`) rather than a room seen from one side.
  bool object = false;
  // Object fixtures (implies `object`): bodies_h's named motion instead of the built-in objects.
  std::string motion;
  bool rgba = false;             // D-NeRF frames as RGBA with a transparent sky, as D-NeRF's are
  bool mixed_distances = false;  // cameras at three distances and three focal lengths in turn
  // > 0: fused.ply holds this many random points in [-1.3, 1.3]^3 with random colours (4DGaussians'
  // synthetic recipe) instead of points3D.ply's surface samples.
  int random_init = 0;
  // Every frame shows the scene at t = 0 (times still run 0..1): a capture of a scene that does not move.
  bool still = false;
  // Surfaces carry a white specular highlight (Scene::specular): colour depends on the viewpoint.
  bool glossy = false;
};

// Throws std::invalid_argument naming the bad value.
void check_options(const SynthOptions& options);

std::string camera_dir_name(int cam);    // "cam07"
std::string frame_file_name(int frame);  // "0012.png"

// Called after each image with (images done, images in all).
using ProgressFn = std::function<void(uint64_t done, uint64_t total)>;

// Throws std::invalid_argument for bad options or when `out` exists and is not an empty
// directory (a dataset is never written over), std::runtime_error when writing fails.
void write_dataset(const std::filesystem::path& out, const SynthOptions& options, const ProgressFn& progress = {});

}  // namespace s4d::synth
