// validate(TrainConfig): the range of every setting, checked wherever settings come from (the
// command line, --set, a run's run.json, the presets), in one message format. The ranges are those
// the trainer needs to run at all (a zero interval divides by zero, a zero learning rate has no
// log-linear schedule) and the deformation kernels' limits (s4d_deform.h); taste is left alone.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "s4d/deform/field_config.h"
#include "s4d/run/train_config.h"
#include "s4d_deform.h"

namespace s4d::run {

namespace {

template <class F>
std::string show_float(F v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char text[64];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, v);  // shortest that reads back
  return std::string(text, r.ptr);
}
std::string show(double v) { return show_float(v); }
std::string show(float v) { return show_float(v); }
std::string show(uint32_t v) { return std::to_string(v); }
std::string show(int v) { return std::to_string(v); }
template <class Range>
std::string show_all(const Range& values) {
  std::string out = "[";
  for (const auto& v : values) out += (out.size() > 1 ? ", " : "") + show(v);
  return out + "]";
}

struct Checker {
  const std::string& source;
  const std::map<std::string, std::string>& flags;

  [[noreturn]] void refuse(const char* key, const std::string& value, const std::string& why) const {
    const auto flag = flags.find(key);
    if (flag != flags.end()) throw std::runtime_error(flag->second + " " + value + ": " + why);
    throw std::runtime_error(setting_error(source, key, value, why));
  }
  template <class T>
  void require(bool ok, const char* key, const T& value, const std::string& why) const {
    if (!ok) refuse(key, show(value), why);
  }
  template <class Range>
  void require_all(bool ok, const char* key, const Range& values, const std::string& why) const {
    if (!ok) refuse(key, show_all(values), why);
  }
  void at_least(const char* key, uint32_t v, uint32_t lo) const { require(v >= lo, key, v, "must be at least " + std::to_string(lo)); }
  void interval(const char* key, uint32_t v) const { require(v >= 1, key, v, "must be at least 1 (an interval in iterations)"); }
  template <class F>
  void fraction(const char* key, F v) const {
    require(std::isfinite(v) && v >= 0 && v <= 1, key, v, "must be in [0, 1]");
  }
  template <class F>
  void non_negative(const char* key, F v) const {
    require(std::isfinite(v) && v >= 0, key, v, "must be a finite number >= 0");
  }
  template <class F>
  void positive(const char* key, F v, const char* what = "") const {
    require(std::isfinite(v) && v > 0, key, v, std::string(what) + "must be a finite number > 0");
  }
  void learning_rate(const char* key, double v) const { positive(key, v, "a learning rate "); }
};

}  // namespace

std::string setting_error(const std::string& source, const std::string& key, const std::string& value, const std::string& why) {
  return source + ": field '" + key + "' = " + value + ": " + why;
}

void validate(const TrainConfig& c, const std::string& source, const std::map<std::string, std::string>& flags) {
  const Checker check{source, flags};
  // Data and schedule.
  check.at_least("iterations", c.iterations, 1);
  check.non_negative("time_budget", c.time_budget);
  check.require(c.downscale >= 1, "downscale", c.downscale, "must be at least 1");
  check.require(std::isfinite(c.max_time) && c.max_time >= 0 && c.max_time <= 1, "max_time", c.max_time,
                "must be a time in [0, 1]");
  // Negative: chosen from the data when a run starts (data_recipe.h); a run's run.json holds the choice.
  check.require(std::isfinite(c.static_max_time) && c.static_max_time <= 1, "static_max_time", c.static_max_time,
                "must be a time in [0, 1], or negative to choose it from the data");
  check.fraction("fine_time_ramp", c.fine_time_ramp);
  check.fraction("fine_time_front", c.fine_time_front);
  for (float b : c.background)
    check.require_all(std::isfinite(b) && b >= 0 && b <= 1, "background", c.background, "each component must be in [0, 1]");
  // Model and loss.
  check.require(c.sh_degree >= 0 && c.sh_degree <= 3, "sh_degree", c.sh_degree, "must be 0..3");
  check.interval("sh_up_every", c.sh_up_every);
  check.at_least("random_init_points", c.random_init_points, 1);
  check.fraction("ssim_weight", c.ssim_weight);
  check.fraction("fine_ssim_weight", c.fine_ssim_weight);
  // Learning rates: log-linear schedules take their logarithm.
  const std::pair<const char*, double> rates[] = {
      {"means_lr", c.means_lr},   {"means_lr_final", c.means_lr_final}, {"sh_dc_lr", c.sh_dc_lr},
      {"sh_rest_lr", c.sh_rest_lr}, {"opacity_lr", c.opacity_lr},       {"scaling_lr", c.scaling_lr},
      {"rotation_lr", c.rotation_lr}, {"lr_scale", c.lr_scale},         {"deform_lr", c.deform_lr},
      {"deform_lr_final", c.deform_lr_final}, {"grid_lr", c.grid_lr},  {"grid_lr_final", c.grid_lr_final}};
  for (const auto& [key, rate] : rates) check.learning_rate(key, rate);
  // Densification (the trainer takes iteration % interval).
  check.interval("densify_every", c.densify_every);
  check.interval("opacity_reset_every", c.opacity_reset_every);
  check.non_negative("grad_threshold", c.grad_threshold);
  check.fraction("percent_dense", c.percent_dense);
  check.fraction("min_opacity", c.min_opacity);
  check.positive("max_screen_radius", c.max_screen_radius);
  check.at_least("budget", c.budget, 1);
  check.require(c.budget_start >= 0 && c.budget_start <= 1, "budget_start", c.budget_start,
                "must be in [0, 1] (a share of budget to start densifying to; 0: off)");
  check.require(c.seed_views <= 64, "seed_views", c.seed_views, "must be at most 64 (views rendered at each densification)");
  // The 4DGS stage and its field (the kernels' limits, s4d_deform.h).
  check.at_least("fine_batch", c.fine_batch, 1);
  for (uint32_t r : c.field_resolution)
    check.require_all(r >= S4D_DEFORM_MIN_RESOLUTION, "field_resolution", c.field_resolution,
                      "each must be at least " + std::to_string(S4D_DEFORM_MIN_RESOLUTION));
  check.require_all(std::isfinite(c.field_time[0]) && std::isfinite(c.field_time[1]) && c.field_time[1] > c.field_time[0],
                    "field_time", c.field_time, "must be two finite times, the second larger");
  check.require_all(!c.field_multires.empty() && c.field_multires.size() <= S4D_DEFORM_MAX_LEVELS, "field_multires",
                    c.field_multires, "needs 1.." + std::to_string(S4D_DEFORM_MAX_LEVELS) + " levels");
  for (uint32_t m : c.field_multires) check.require_all(m >= 1, "field_multires", c.field_multires, "each must be at least 1");
  check.require(c.field_channels >= 1 && c.field_channels <= S4D_DEFORM_MAX_CHANNELS, "field_channels", c.field_channels,
                "must be 1.." + std::to_string(S4D_DEFORM_MAX_CHANNELS));
  check.require(uint64_t{c.field_channels} * c.field_multires.size() <= S4D_DEFORM_MAX_FEAT, "field_channels", c.field_channels,
                "times " + std::to_string(c.field_multires.size()) + " levels must be at most " +
                    std::to_string(S4D_DEFORM_MAX_FEAT));
  check.require(c.field_width >= 1 && c.field_width <= S4D_DEFORM_MAX_WIDTH, "field_width", c.field_width,
                "must be 1.." + std::to_string(S4D_DEFORM_MAX_WIDTH));
  check.require(c.field_trunk_extra <= S4D_DEFORM_MAX_TRUNK_EXTRA, "field_trunk_extra", c.field_trunk_extra,
                "must be 0.." + std::to_string(S4D_DEFORM_MAX_TRUNK_EXTRA));
  check.require(c.field_heads >= 1 && c.field_heads < (1u << S4D_DEFORM_HEADS), "field_heads", c.field_heads,
                "must be a non-empty set of the " + std::to_string(S4D_DEFORM_HEADS) + " head bits (1.." +
                    std::to_string((1u << S4D_DEFORM_HEADS) - 1) + ")");
  try {  // what is left of the kernels' limits: the planes' 32-bit indexing
    deform::deform_shape(field_config(c, {-1, -1, -1}, {1, 1, 1}));
  } catch (const std::invalid_argument& e) {
    check.require_all(false, "field_resolution", c.field_resolution, e.what());
  }
  check.non_negative("plane_tv_weight", c.plane_tv_weight);
  check.non_negative("time_smoothness_weight", c.time_smoothness_weight);
  check.non_negative("l1_time_planes_weight", c.l1_time_planes_weight);
  check.non_negative("static_motion", c.static_motion);
  check.at_least("motion_samples", c.motion_samples, 2);  // motion is measured between two times at least
  check.interval("motion_every", c.motion_every);
  check.require(c.field_fit >= 0 && c.field_fit < 1, "field_fit", c.field_fit, "must be in [0, 1) (a fraction of the fine stage after its time window opens; 0: off)");
  // Runs.
  check.interval("test_every", c.test_every);
  check.interval("checkpoint_every", c.checkpoint_every);
}

}  // namespace s4d::run
