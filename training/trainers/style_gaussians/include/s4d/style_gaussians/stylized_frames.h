// Stage 3 of Style4D: every camera's frames of a dataset restyled after one style image by a 2D
// stylizer, written as PNGs at the training resolution and cached: a second call with the same
// inputs reuses them. The result is a dataset (the same cameras and times) whose images are the
// stylized frames, what stage 4 trains against and the "scratch" ablation retrains 4DGS on.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/data/dataset.h"
#include "s4d/io/image_io.h"
#include "s4d/frame_stylizers/stylizer.h"

namespace s4d::style_gaussians {

struct StylizedFrames {
  data::Dataset dataset;  // the content's views with `image` pointing at the stylized PNGs (downscale 1)
  bool reused = false;    // every frame came from the cache
  double seconds = 0;     // stylization time (0 when reused)
  // Per sequence (a DyNeRF camera, or a D-NeRF split in time order): the temporal warp error of the
  // content frames and of the stylized frames (warp_error.h), and the sequence's name.
  struct Sequence {
    std::string name;
    double content_warp_error = 0, stylized_warp_error = 0;
  };
  std::vector<Sequence> sequences;
  nlohmann::json to_json() const;
};

// Stylizes each sequence of `content` (frames loaded as training loads them: downscaled, composited
// on the background) into `out_dir`/<view name>.png with `out_dir`/manifest.json describing the
// inputs (`key`: stylizer, strength, seed, style image identity). When the manifest's key and frame
// list match and every PNG is there, nothing is recomputed. Throws std::runtime_error naming the
// file for unreadable frames or unwritable outputs.
StylizedFrames stylize_dataset(const data::Dataset& content, const frame_stylizers::Stylizer& stylizer, const io::ImageF& style,
                               const frame_stylizers::StylizeSettings& settings, const nlohmann::json& key,
                               const std::filesystem::path& out_dir);

}  // namespace s4d::style_gaussians
