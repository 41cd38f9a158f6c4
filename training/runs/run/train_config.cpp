#include "s4d/run/train_config.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <stdexcept>
#include <type_traits>

#include <nlohmann/json.hpp>

namespace s4d::run {

TrainConfig preset_config(const std::string& name) {
  TrainConfig c;
  c.preset = name;
  c.seed_views = 4;
  c.sh_degree_auto = true;
  c.field_fit = 0.2;
  c.budget_start = 0.25;
  if (name == "default") {
    // 4DGaussians' recipe (ALGORITHMS.md 3.3): a 3,000-step coarse (static) stage, densified from
    // step 500 every 100 (its opacity reset at step 3,000 falls in the stage's last densification
    // interval, where the trainer skips resets), then the fine stage's 14,000 steps
    // (DyNeRF; its D-NeRF scenes take 20,000: --fine-iters 20000).
    c.iterations = 3000;
    return c;
  }
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
    // Fine stage sized for lavapipe's speed: the per-layer MLP kernels run any width there
    // (llvmpipe's loop limit does not cap them), but 4DGaussians' width-128, five-head field
    // costs ~24x this one per Gaussian (docs/training.md, "The deformation field").
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

Stage last_stage(const TrainConfig& config) { return config.fine_iterations > 0 ? Stage::fine : Stage::coarse; }

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
  f.time_range = c.field_time;
  return f;
}


#define S4D_CONFIG_FIELDS(X)                                                                                     \
  X(preset) X(iterations) X(seed) X(downscale) X(frames) X(max_time) X(static_max_time) X(fine_time_ramp) X(fine_time_front) X(background) X(sh_degree) X(sh_up_every) X(sh_degree_auto)              \
  X(random_init_points) X(ssim_weight) X(means_lr) X(means_lr_final) X(sh_dc_lr) X(sh_rest_lr) X(opacity_lr)     \
  X(scaling_lr) X(rotation_lr) X(lr_scale) X(densify_from) X(densify_until) X(densify_every) X(opacity_reset_every)          \
  X(grad_threshold) X(percent_dense) X(min_opacity) X(max_screen_radius) X(budget) X(budget_start) X(seed_views) X(test_every)               \
  X(checkpoint_every) X(fine_iterations) X(fine_batch) X(fine_ssim_weight) X(fine_densify_until)      \
  X(field_resolution) X(field_time) X(field_multires) X(field_channels) X(field_width) X(field_trunk_extra) X(field_heads)       \
  X(deform_lr) X(deform_lr_final) X(grid_lr) X(grid_lr_final) X(plane_tv_weight) X(time_smoothness_weight)       \
  X(l1_time_planes_weight) X(static_motion) X(motion_samples) X(motion_every) X(field_fit) X(time_budget)

nlohmann::json to_json(const TrainConfig& c) {
  nlohmann::json j;
#define S4D_PUT(field) j[#field] = c.field;
  S4D_CONFIG_FIELDS(S4D_PUT)
#undef S4D_PUT
  return j;
}

namespace {

// Reads one setting's JSON value into its field's type; `whole` is the key's value as written (an
// array for an element), shown in the message. Counts are whole numbers in their type's range (the
// JSON library would wrap -1 to 4294967295 and truncate 2.5); floats within the float range.
struct SettingReader {
  const std::string& source;
  const char* key;
  const nlohmann::json& whole;

  [[noreturn]] void bad(const std::string& why) const { throw std::runtime_error(setting_error(source, key, whole.dump(), why)); }

  void read(const nlohmann::json& v, std::string& out) const {
    if (!v.is_string()) bad("expected a string");
    out = v.get<std::string>();
  }
  template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
  void read(const nlohmann::json& v, T& out) const {
    constexpr auto lo = std::numeric_limits<T>::min();
    constexpr auto hi = std::numeric_limits<T>::max();
    const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
    if (!v.is_number()) bad("expected a whole number");
    if (v.is_number_float()) {
      const double d = v.get<double>();
      if (!std::isfinite(d) || d != std::floor(d)) bad("expected a whole number");
      if (d < static_cast<double>(lo) || d > static_cast<double>(hi)) bad("must be in " + range);
      out = static_cast<T>(d);
    } else if (v.is_number_unsigned()) {
      const uint64_t u = v.get<uint64_t>();
      if (u > static_cast<uint64_t>(hi)) bad("must be in " + range);
      out = static_cast<T>(u);
    } else {
      const int64_t i = v.get<int64_t>();
      if (i < static_cast<int64_t>(lo)) bad(std::is_unsigned_v<T> ? "must not be negative" : "must be in " + range);
      if (i > static_cast<int64_t>(hi)) bad("must be in " + range);
      out = static_cast<T>(i);
    }
  }
  void read(const nlohmann::json& v, bool& out) const {
    if (!v.is_boolean()) bad("expected true or false");
    out = v.get<bool>();
  }
  void read(const nlohmann::json& v, double& out) const {
    if (!v.is_number()) bad("expected a number");
    out = v.get<double>();
  }
  void read(const nlohmann::json& v, float& out) const {
    double d = 0;
    read(v, d);
    if (std::isfinite(d) && std::fabs(d) > std::numeric_limits<float>::max()) bad("outside the float range");
    out = static_cast<float>(d);
  }
  template <class T, size_t N>
  void read(const nlohmann::json& v, std::array<T, N>& out) const {
    if (!v.is_array() || v.size() != N) bad("expected an array of " + std::to_string(N) + " numbers");
    for (size_t k = 0; k < N; ++k) read(v[k], out[k]);
  }
  template <class T>
  void read(const nlohmann::json& v, std::vector<T>& out) const {
    if (!v.is_array()) bad("expected an array of numbers");
    out.resize(v.size());
    for (size_t k = 0; k < v.size(); ++k) read(v[k], out[k]);
  }
};

}  // namespace

TrainConfig config_from_json(const nlohmann::json& j, const std::string& source) {
  if (!j.is_object())
    throw std::runtime_error(source + ": the training settings are " + (j.is_null() ? std::string("null") : "a JSON " + std::string(j.type_name())) +
                             ", expected a JSON object");
  static const std::set<std::string> known = {
#define S4D_NAME(field) #field,
      S4D_CONFIG_FIELDS(S4D_NAME)
#undef S4D_NAME
  };
  for (const auto& [key, value] : j.items())
    if (!known.contains(key)) throw std::runtime_error(source + ": field '" + key + "': not a training setting (train.json lists them)");
  TrainConfig c;
#define S4D_GET(field) \
  if (j.contains(#field)) SettingReader{source, #field, j.at(#field)}.read(j.at(#field), c.field);
  S4D_CONFIG_FIELDS(S4D_GET)
#undef S4D_GET
  validate(c, source);
  return c;
}

}  // namespace s4d::run
