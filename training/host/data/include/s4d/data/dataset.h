// The dataset representation every layout loads into: a list of views (camera, time, image file,
// split) plus scene-level facts the trainer needs (camera extent, optional initial points).
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "s4d/io/nerf_cameras.h"

namespace s4d::data {

struct View {  // one training or test image
  std::string name;       // "cam03/0012" (DyNeRF, frame folder or video) or "train/r_000" (D-NeRF: split folder kept, so names are unique)
  io::CameraView camera;  // pose (world_to_cam, OpenCV axes: x right, y down, z forward) and intrinsics of the
                          // downscaled image; pixel (i, j) is centred at (i + 0.5, j + 0.5), u = fx x / z + cx
  double time = 0;        // in [0, 1]
  int camera_index = -1;  // physical camera (DyNeRF), -1 when every view has its own (D-NeRF)
  std::filesystem::path image;  // file to load (full resolution; FrameCache downscales)
  int frame_in_file = -1;       // -1: `image` is an image file; >= 0: `image` is a video and this its frame
  // Box-filter factor FrameCache applies to this view's file; 0: the dataset's downscale. 1 for a
  // file the layout ships already downscaled (HyperNeRF's rgb/Nx/).
  int file_downscale = 0;
  bool test = false;            // held out for evaluation
};

struct Dataset {
  std::string kind;    // loader family: "dynerf", "dnerf", "hypernerf" or "colmap"
  std::string layout;  // the exact layout found, named in run.json and by check-data (see layouts below)
  std::filesystem::path root;
  std::vector<View> views;
  double extent = 0;  // 1.1 x max distance of train camera centres from their mean (3DGS cameras_extent)
  int downscale = 1;  // integer box-filter factor applied to every image; intrinsics already scaled
  // Optional initial point cloud (the layout's own file, see finish_dataset): [P * 3] positions and
  // [P * 3] colours in [0, 1]; points_file is the file they came from (empty: none found).
  std::vector<float> points, colors;
  std::filesystem::path points_file;
  std::array<float, 3> background{};  // RGBA frames are composited on this, and renders drawn on it
  // Where the background came from: "option" (LoadOptions::background), "alpha" (frames have alpha:
  // the layout's convention), "borders" (opaque frames with a uniform border colour), "layout"
  // (the layout's default; "layout (opaque frames)" when frames were probed and gave no answer).
  std::string background_source;
  std::string background_conflict;  // non-empty: the frames disagree with the background asked for
};

struct LoadOptions {
  int downscale = 1;  // >= 1
  // Unset: found from the frames (Dataset::background_source); for frames with alpha or real
  // captures, the layout's own default, black for DyNeRF and white for D-NeRF (what D-NeRF and
  // 4DGaussians train with).
  std::optional<std::array<float, 3>> background;
  // Decode a few training frames to find the background (alpha, or a uniform border colour) and to
  // check an explicit one against them. Off when reopening a run, whose background is settled.
  bool probe_background = true;
  // Only the frames (distinct times, in order) with index in [first, end), their times mapped back
  // onto [0, 1]: a cap for long captures (--frames). Unset: every frame.
  std::optional<std::pair<int, int>> frames;
};

// "N" -> [0, N), "A:B" -> [A, B). Throws std::invalid_argument naming `option` for anything else.
std::pair<int, int> parse_frame_range(const std::string& text, const std::string& option = "--frames");

// Layouts (Dataset::layout), each with its loader:
//   "dynerf-frames"      poses_bounds.npy + camNN/NNNN.png                       load_dynerf
//   "dynerf-video"       poses_bounds.npy + camNN.mp4                            load_dynerf
//   "dynerf-4dgaussians" poses_bounds.npy + camNN/images/NNNN.png (4DGaussians' preprocessed Neu3D)
//   "dnerf"              transforms_{train,val,test}.json with per-frame time    load_dnerf
//   "hypernerf"          dataset.json, metadata.json, camera/*.json, rgb/Nx/      load_hypernerf
//   "colmap-multiview"   sparse/0/{cameras,images,points3D}.{bin,txt} + one frame folder per camera  load_colmap

// DyNeRF / Neu3D: poses_bounds.npy plus, per camera, camNN/NNNN.png frames (or camNN/images/NNNN.png)
// or a camNN.mp4 video. See dynerf.cpp for the conventions.
Dataset load_dynerf(const std::filesystem::path& root, const LoadOptions& options = {});

// D-NeRF: transforms_{train,val,test}.json (val optional, loaded as test views) with per-frame time.
Dataset load_dnerf(const std::filesystem::path& root, const LoadOptions& options = {});

// HyperNeRF / Nerfies: see hypernerf.cpp for the conventions.
Dataset load_hypernerf(const std::filesystem::path& root, const LoadOptions& options = {});

// A COLMAP reconstruction of a multi-camera rig plus one frame folder per camera: see colmap.cpp.
Dataset load_colmap(const std::filesystem::path& root, const LoadOptions& options = {});

// Detects the layout: poses_bounds.npy -> DyNeRF, transforms_train.json -> D-NeRF, dataset.json ->
// HyperNeRF, sparse/0/ -> COLMAP; otherwise throws std::runtime_error naming the directory and the
// files looked for.
Dataset load_dataset(const std::filesystem::path& root, const LoadOptions& options = {});

}  // namespace s4d::data
