// Trainer::Impl's fit of the deformation field's box and time axis to what moves (field_box.h).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "s4d/deform/field_resample.h"
#include "s4d/run/train_config.h"
#include "s4d/train/field_box.h"
#include "trainer_impl.h"

namespace s4d::train {

namespace {

// The time fit measures at most this many moving Gaussians, over at most this many texel intervals.
constexpr size_t kTimeFitGaussians = 4096;
constexpr uint32_t kTimeFitIntervals = 64;

}  // namespace

bool Trainer::Impl::fit_field_box_if_due(double seconds) {
  const uint32_t due = field_fit_step(config);
  if (!fine() || !field || field_fitted || due == 0 || iteration < due) return false;
  std::vector<float> lo, hi;
  path_bounds(lo, hi);
  // What counts as moving: the motion split's threshold (fast's 0.01 x extent where it is off).
  const double limit = (config.static_motion > 0 ? config.static_motion : 0.01) * dataset.extent;
  const auto& r = config.field_resolution;
  FieldBox box = fit_field_box(lo, hi, aabb_min, aabb_max, {r[0], r[1], r[2]}, limit);
  box.at_step = iteration;
  FieldTime time = fit_time(lo, hi, limit);
  time.at_step = iteration;

  if (box.fitted || time.fitted) {
    model::Checkpoint cp = snapshot(seconds);
    const deform::FieldConfig from = run::field_config(config, aabb_min, aabb_max);
    for (int k = 0; k < 3; ++k) config.field_resolution[k] = box.resolution[k];
    config.field_resolution[3] = time.resolution;
    const deform::FieldConfig to = run::field_config(config, box.min, box.max);
    for (auto& [name, values] : cp.extra)
      if (name.rfind("field.planes", 0) == 0) values = deform::resample_planes(from, to, values);  // with its moments
    cp.meta["aabb_min"] = box.min, cp.meta["aabb_max"] = box.max, cp.meta["field_resolution"] = config.field_resolution;
    restore(cp);  // rebuilds the field on the new box
  }
  field_fitted = true;
  facts["recipe"]["field_box"] = box.json();
  facts["recipe"]["field_time"] = time.json();
  save_run_json();     // the field's resolution, for a resumed run and for rendering
  checkpoint(seconds);  // the box and that the fit is done

  std::string line = "deformation field box at fine iteration " + std::to_string(iteration) + ": " + box.why;
  for (int k = 0; k < 3 && box.fitted; ++k) {
    char axis[128];
    std::snprintf(axis, sizeof axis, "%s %c [%.3g, %.3g] (was [%.3g, %.3g])", k ? "," : ";", "xyz"[k], box.min[k], box.max[k],
                  box.old_min[k], box.old_max[k]);
    line += axis;
  }
  std::cerr << line << "\n" << "deformation field time axis at fine iteration " << iteration << ": " << time.why << "\n";
  return true;
}

FieldTime Trainer::Impl::fit_time(const std::vector<float>& lo, const std::vector<float>& hi, double move_limit) {
  const uint32_t texels = config.field_resolution[3];
  FieldTime none{.old_resolution = texels, .resolution = texels, .tolerance = move_limit};
  if (head(S4D_DEFORM_HEAD_OPACITY) || head(S4D_DEFORM_HEAD_SH)) {
    none.why = "the field deforms opacity or colour, which a path in space does not show: the time axis stays";
    return none;
  }
  // Four samples over [0, 1] per texel interval of the whole axis (at most kTimeFitIntervals
  // intervals): the paths between the texels show what fewer texels miss.
  const uint32_t samples = 4 * std::min(texels - 1, kTimeFitIntervals) + 1;
  const uint32_t n = gaussians->size();
  std::vector<uint32_t> movers;
  for (uint32_t i = 0; i < n; ++i)
    if (path_moves(lo, hi, i, move_limit)) movers.push_back(i);
  // An even subset of at most kTimeFitGaussians: the quantile needs no more, and host memory stays small.
  const size_t stride = (movers.size() + kTimeFitGaussians - 1) / kTimeFitGaussians;
  std::vector<uint32_t> measured;
  for (size_t m = 0; m < movers.size(); m += std::max<size_t>(1, stride)) measured.push_back(movers[m]);
  // A Gaussian's state in world units: its mean, its three extents, and its unit quaternion times
  // its largest extent (how far a rotation moves its surface, to first order).
  constexpr uint32_t kDims = 10;
  const uint32_t still = still_count;
  still_count = 0;  // every Gaussian deformed
  std::vector<float> paths;
  paths.reserve(size_t{samples} * measured.size() * kDims);
  for (uint32_t s = 0; s < samples; ++s) {
    const splat::GaussianParams p = deform_to(double(s) / (samples - 1));
    const std::vector<float> means = ctx.download<float>(*p[splat::Attr::means], size_t{n} * 3);
    const std::vector<float> log_scales = ctx.download<float>(*p[splat::Attr::log_scales], size_t{n} * 3);
    const std::vector<float> quats = ctx.download<float>(*p[splat::Attr::quats], size_t{n} * 4);
    for (uint32_t i : measured) {
      float extent[3], largest = 0;
      for (int k = 0; k < 3; ++k) extent[k] = std::exp(log_scales[i * 3 + k]), largest = std::max(largest, extent[k]);
      const float* q = &quats[i * 4];
      const float norm = std::max(1e-12f, std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]));
      paths.insert(paths.end(), {means[i * 3], means[i * 3 + 1], means[i * 3 + 2], extent[0], extent[1], extent[2],
                                 q[0] / norm * largest, q[1] / norm * largest, q[2] / norm * largest, q[3] / norm * largest});
    }
  }
  still_count = still;
  FieldTime fit =
      fit_field_time(paths, samples, kDims, std::vector<uint8_t>(measured.size(), 1), texels, config.field_time, move_limit);
  fit.moving = static_cast<uint32_t>(movers.size());
  return fit;
}

}  // namespace s4d::train
