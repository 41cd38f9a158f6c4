// A trained style of a run (stage 4, `style4d stylize`): what it changes on the run's Gaussians, kept
// apart from the geometry so that one run holds any number of styles side by side, each one small
// file, switched at render or view time without retraining.
//
//   RUN/style/NAME/style.s4dstyle   this file (the checkpoint container format, checkpoint.h, with
//                                   no Gaussians: only the arrays below and the settings)
//   RUN/style/NAME/stylize.json     results; RUN/style/NAME/stylized/ the stage-3 frames
//
// The colours and opacities are stored as changes (deltas) to the run's own values, so that they
// apply unchanged to a 4DGS run whose field also moves opacity or SH: rendered = run's value at t +
// delta. Method "scratch" (the ablation that retrains 4DGS on the stylized frames) has no arrays:
// its geometry is the run in RUN/style/NAME/run.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/run/names.h"

namespace s4d::run {

struct StyleFile {
  StyleMethod method = StyleMethod::full;  // full: with sh_delta, opacity_delta, mlp; colors: no mlp; scratch: none
  nlohmann::json settings;      // how it was trained (style image, stylizer, iterations, ...)
  uint32_t count = 0;           // Gaussians of the run it belongs to
  uint32_t sh_coeffs = 0;       // SH coefficients per channel of sh_delta
  std::vector<float> sh_delta;       // [count * sh_coeffs * 3], the run's layout
  std::vector<float> opacity_delta;  // [count], added to the opacity logit
  std::vector<float> mlp;            // [count * S4D_STYLE_MLP_STRIDE], empty without MLPs
  DepthInput depth_input = DepthInput::relative;
  float depth_scale = 1.0f;
  bool input_sigmoid = false;
};

std::filesystem::path style_dir(const std::filesystem::path& run_root, const std::string& name);
std::filesystem::path style_file_path(const std::filesystem::path& run_root, const std::string& name);
// The copy of the style image the style was trained with (8-bit PNG), kept so that the run folder
// alone scores its styles; styles from before it existed name the image in request.json only.
std::filesystem::path style_image_path(const std::filesystem::path& run_root, const std::string& name);

// Atomic; throws std::invalid_argument on inconsistent sizes or non-finite values (nothing written).
void write_style_file(const std::filesystem::path& path, const StyleFile& style);

// Throws std::runtime_error naming the file and what is wrong (missing, not a style file, arrays of
// the wrong size, non-finite values, unknown method or depth input).
StyleFile read_style_file(const std::filesystem::path& path);

// The names of the run's finished styles (folders under RUN/style with a style file), sorted.
std::vector<std::string> list_styles(const std::filesystem::path& run_root);

}  // namespace s4d::run
