// Settings of stage 4 (`style4d stylize`): which ablation, how long, the learning rates, the loss,
// and the open choices of the per-Gaussian MLP (ALGORITHMS.md 4.3), each a flag with a default. Two
// named settings give the defaults (style_setting()): "tuned", ours, and "paper", Style4D's as
// published.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/run/style_file.h"

namespace s4d::style_gaussians {

struct StyleConfig {
  // The named setting the other fields started from: tuned or paper (style_setting()).
  std::string setting = "tuned";
  // full: per-Gaussian MLPs + colours and opacities (the paper's method); colors: the two-stage
  // scheme without MLPs (only colours and opacities retrained); scratch: 4DGS trained from scratch
  // on the stylized frames.
  run::StyleMethod method = run::StyleMethod::full;
  std::string stylizer = "patch";
  float strength = 1.0f;            // of the 2D stylizer
  uint32_t iterations = 1500;
  // Method "full": the MLPs join for the last mlp_iterations steps; before, only the colours and
  // opacities train, on the plain rasterizer (about 6x cheaper per step on lavapipe). With the
  // "identity" initialisation the MLPs start by adding nothing, so joining changes no pixel.
  uint32_t mlp_iterations = 300;
  // Training views per step; their gradients are summed, which gives Adam the same step as their
  // mean (it divides by the gradients' RMS; eps 1e-15 aside).
  uint32_t batch = 1;
  uint32_t seed = 0;
  bool train_colors = true;         // "full": also update the base colours (SH) and opacities
  // Learning rates: the 4DGaussians feature rates and SuperGaussians' MLP rate (ALGORITHMS.md 4.3).
  double sh_dc_lr = 0.0025, sh_rest_lr = 0.000125, opacity_lr = 0.05, mlp_lr = 2.5e-4;
  // 0: mlp_lr throughout; else the MLPs' rate decays log-linearly from mlp_lr to this over their
  // mlp_iterations steps (3DGS's get_expon_lr_func, optim::LogLinearSchedule).
  double mlp_lr_final = 0;
  float ssim_weight = 0.0f;         // 0: plain L1, as the paper
  float tv_weight = 0.05f;          // squared image TV on the render (tv_loss.h)
  run::DepthInput depth_input = run::DepthInput::relative;
  float depth_scale = 0;            // relative depth: t* - z times this; 0 = 1 / (3 x median Gaussian scale)
  bool input_sigmoid = false;       // SuperGaussians squashes the MLP inputs with a sigmoid
  std::string mlp_init = "identity"; // "uniform": SuperGaussians' U(-0.5, 0.5) weights, zero biases;
                                     // "identity": the same with a zero last layer (adds nothing at first)
  // Stylize only a region: empty, or a world-space box (min x, y, z, max x, y, z); Gaussians whose
  // centre at the first frame lies outside keep the run's look exactly.
  std::vector<float> region;
  uint32_t test_every = 500, checkpoint_every = 500;
};

// The defaults of a named setting. "tuned" (StyleConfig's own): the MLPs join for the last 300 of
// 1500 steps from a zero last layer (mlp_init identity), at a constant 2.5e-4, one view per step.
// "paper" (ALGORITHMS.md 4.6): the MLPs train from the first step from SuperGaussians' U(-0.5, 0.5)
// weights, their rate decays 1e-4 -> 1e-5, two views per step; L1 + TV and the colour rates as tuned.
// std::invalid_argument "style settings: setting 'NAME' is not tuned or paper" otherwise.
StyleConfig style_setting(const std::string& name);
// Sets the stage-4 length; when the MLPs trained for all of it (mlp_iterations == iterations, as in
// "paper") they still do.
void set_iterations(StyleConfig& c, uint32_t iterations);

nlohmann::json to_json(const StyleConfig& c);
// Fields that are absent take the defaults of the JSON's "setting" (tuned when absent too).
// Throws std::invalid_argument naming the field for unknown keys, wrong types or values out of range.
StyleConfig style_config_from_json(const nlohmann::json& j);
void validate(const StyleConfig& c);
// The method of --method or a settings file; std::invalid_argument "style settings: method 'NAME' is
// not full, colors or scratch" otherwise.
run::StyleMethod method_setting(const std::string& name);

}  // namespace s4d::style_gaussians
