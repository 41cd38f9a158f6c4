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

void Trainer::Impl::fit_field_box_if_due(double seconds) {
  const uint32_t due = field_fit_step(config);
  if (!fine() || !field || field_fitted || due == 0 || iteration < due) return;
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
}

FieldTime Trainer::Impl::fit_time(const std::vector<float>& lo, const std::vector<float>& hi, double move_limit) {
  // Four samples per texel interval: the paths between the texels show what fewer texels miss.
  const uint32_t texels = config.field_resolution[3], samples = 4 * (texels - 1) + 1;
  const uint32_t n = gaussians->size();
  std::vector<uint8_t> moving(n);
  for (uint32_t i = 0; i < n; ++i) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += double(hi[i * 3 + k] - lo[i * 3 + k]) * (hi[i * 3 + k] - lo[i * 3 + k]);
    moving[i] = std::sqrt(d2) >= move_limit;
  }
  const uint32_t still = still_count;
  still_count = 0;  // every Gaussian deformed
  std::vector<float> paths;
  paths.reserve(size_t{samples} * n * 3);
  const auto& range = config.field_time;
  for (uint32_t s = 0; s < samples; ++s) {
    const splat::GaussianParams p = deform_to(range[0] + (double(range[1]) - range[0]) * s / (samples - 1));
    const std::vector<float> means = ctx.download<float>(*p[splat::Attr::means], size_t{n} * 3);
    paths.insert(paths.end(), means.begin(), means.end());
  }
  still_count = still;
  return fit_field_time(paths, samples, moving, texels, move_limit);
}

}  // namespace s4d::train
