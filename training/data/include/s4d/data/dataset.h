// The dataset representation every layout loads into: a list of views (camera, time, image file,
// split) plus scene-level facts the trainer needs (camera extent, optional initial points).
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <string>
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
  bool test = false;            // held out for evaluation
};

struct Dataset {
  std::string kind;  // "dynerf" or "dnerf"
  std::filesystem::path root;
  std::vector<View> views;
  double extent = 0;  // 1.1 x max distance of train camera centres from their mean (3DGS cameras_extent)
  int downscale = 1;  // integer box-filter factor applied to every image; intrinsics already scaled
  // Optional initial point cloud from <root>/points3D.ply: [P * 3] positions and [P * 3] colours in [0, 1].
  std::vector<float> points, colors;
  std::array<float, 3> background{};  // RGBA frames are composited on this
};

struct LoadOptions {
  int downscale = 1;  // >= 1
  // Unset: the layout's own default, black for DyNeRF (frames are opaque) and white for D-NeRF
  // (what D-NeRF and 4DGaussians train with).
  std::optional<std::array<float, 3>> background;
};

// DyNeRF / Neu3D: poses_bounds.npy plus, per camera, camNN/NNNN.png frames or a camNN.mp4 video. See
// dynerf.cpp for the conventions.
Dataset load_dynerf(const std::filesystem::path& root, const LoadOptions& options = {});

// D-NeRF: transforms_{train,val,test}.json (val optional, loaded as test views) with per-frame time.
Dataset load_dnerf(const std::filesystem::path& root, const LoadOptions& options = {});

// Detects the layout: poses_bounds.npy -> DyNeRF, transforms_train.json -> D-NeRF; otherwise throws
// std::runtime_error naming the directory and both files looked for.
Dataset load_dataset(const std::filesystem::path& root, const LoadOptions& options = {});

}  // namespace s4d::data
