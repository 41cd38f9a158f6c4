#include "s4d/train/train_config.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace s4d::train {

TrainConfig preset_config(const std::string& name) {
  TrainConfig c;
  c.preset = name;
  if (name == "default") return c;  // graphdeco's 30k schedule
  if (name == "fast") {
    // Minutes on lavapipe at 160x120 (measured on the built-in scene's first frame: test PSNR
    // 31.9 dB after 1000 iterations, then falling as a 9-view fit overfits). No opacity reset,
    // which costs ~500 iterations to recover from; SH up to degree 1.
    // 900 iterations since the static stage fits the first frame only (static_max_time below): the
    // budget is full by iteration ~700 and the first frame's loss has flattened.
    c.iterations = 900;
    c.sh_degree = 1;
    c.sh_up_every = 300;
    c.densify_from = 300;
    c.densify_until = 700;
    c.opacity_reset_every = 3000;
    c.budget = 15000;
    c.test_every = 300;
    c.checkpoint_every = 300;
    // Fine stage sized for lavapipe: llvmpipe ends any shader invocation after 65535 loop
    // iterations, which caps the MLP width near 32 (docs/training.md, "The deformation field").
    c.fine_iterations = 1500;
    c.fine_batch = 1;  // 4DGaussians uses 1 for D-NeRF; a 4DGS step costs ~2.5x a static one on lavapipe
    c.field_resolution = {32, 32, 32, 16};
    c.field_channels = 8;
    c.field_width = 32;
    c.field_heads = 7;
    // 1500 fine steps are a tenth of 4DGaussians' 14000: the first frame as the canonical scene, a
    // time curriculum whose newest frames get every other view, and 3x the field's learning rates
    // let the field follow the built-in scene's sliding box to the last frame (docs/training.md, stage 2:
    // 28.4 dB over cam00's 30 frames, against 23.8 dB with 4DGaussians' schedule).
    // The first frame is canonical on a multi-view capture; a monocular one gets every frame
    // (static_max_time < 0 leaves it to the data: data_recipe.h).
    c.static_max_time = -1.0;
    c.fine_time_ramp = 0.6;
    c.fine_time_front = 0.1;
    c.grid_lr *= 3, c.grid_lr_final *= 3, c.deform_lr *= 3, c.deform_lr_final *= 3;
    // Deform only what moves from fine iteration 600 on, re-measured every 300. On the built-in
    // scene the Gaussians' motion over time has a knee (measured on a trained run): 60 % move at
    // most 0.005 x extent, 30 % more than 0.018 x extent; 0.01 sits inside the knee.
    c.fine_densify_until = 600;
    c.static_motion = 0.01f;
    c.motion_every = 300;
    return c;
  }
  if (name == "quality") {
    c.iterations = 40000;
    c.densify_until = 20000;
    c.grad_threshold = 0.00015f;
    c.budget = 3000000;
    return c;
  }
  throw std::invalid_argument("--preset: unknown preset '" + name + "' (fast, default or quality)");
}

void set_iterations(TrainConfig& c, uint32_t iterations) {
  if (iterations == 0) throw std::invalid_argument("--iters: must be at least 1");
  const double f = double(iterations) / c.iterations;
  auto scale = [f](uint32_t& v) { v = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(v * f))); };
  for (uint32_t* v : {&c.densify_from, &c.densify_until, &c.opacity_reset_every, &c.sh_up_every, &c.test_every,
                      &c.checkpoint_every})
    scale(*v);
  c.iterations = iterations;
}

void set_fine_iterations(TrainConfig& c, uint32_t iterations) {
  if (c.fine_iterations > 0) {
    const double f = double(iterations) / c.fine_iterations;
    c.fine_densify_until = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(c.fine_densify_until * f)));
  }
  c.fine_iterations = iterations;
}

int active_sh_degree(const TrainConfig& c, uint32_t iterations_done) {
  return std::min<int>(c.sh_degree, static_cast<int>(iterations_done / std::max<uint32_t>(1, c.sh_up_every)));
}

deform::FieldConfig field_config(const TrainConfig& c, const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
  deform::FieldConfig f;
  f.resolution = c.field_resolution;
  f.multires = c.field_multires;
  f.channels = c.field_channels;
  f.width = c.field_width;
  f.trunk_extra = c.field_trunk_extra;
  f.heads = c.field_heads;
  f.aabb_min = lo;
  f.aabb_max = hi;
  return f;
}


#define S4D_CONFIG_FIELDS(X)                                                                                     \
  X(preset) X(iterations) X(seed) X(downscale) X(max_time) X(static_max_time) X(fine_time_ramp) X(fine_time_front) X(background) X(sh_degree) X(sh_up_every)              \
  X(random_init_points) X(ssim_weight) X(means_lr) X(means_lr_final) X(sh_dc_lr) X(sh_rest_lr) X(opacity_lr)     \
  X(scaling_lr) X(rotation_lr) X(lr_scale) X(densify_from) X(densify_until) X(densify_every) X(opacity_reset_every)          \
  X(grad_threshold) X(percent_dense) X(min_opacity) X(max_screen_radius) X(budget) X(test_every)               \
  X(checkpoint_every) X(fine_iterations) X(fine_batch) X(fine_ssim_weight) X(fine_densify_until)      \
  X(field_resolution) X(field_multires) X(field_channels) X(field_width) X(field_trunk_extra) X(field_heads)       \
  X(deform_lr) X(deform_lr_final) X(grid_lr) X(grid_lr_final) X(plane_tv_weight) X(time_smoothness_weight)       \
  X(l1_time_planes_weight) X(static_motion) X(motion_samples) X(motion_every)

nlohmann::json to_json(const TrainConfig& c) {
  nlohmann::json j;
#define S4D_PUT(field) j[#field] = c.field;
  S4D_CONFIG_FIELDS(S4D_PUT)
#undef S4D_PUT
  return j;
}

TrainConfig config_from_json(const nlohmann::json& j) {
  if (!j.is_object()) throw std::runtime_error("training settings: expected a JSON object");
  TrainConfig c;
#define S4D_GET(field)                                                                                  \
  if (j.contains(#field)) {                                                                             \
    try {                                                                                               \
      j.at(#field).get_to(c.field);                                                                     \
    } catch (const nlohmann::json::exception& e) {                                                      \
      throw std::runtime_error(std::string("training settings: field '" #field "': ") + e.what());     \
    }                                                                                                   \
  }
  S4D_CONFIG_FIELDS(S4D_GET)
#undef S4D_GET
  return c;
}

}  // namespace s4d::train
