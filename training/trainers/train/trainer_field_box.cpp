// Trainer::Impl's fit of the deformation field's box to what moves (field_box.h).
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
  if (!fine() || !field || iteration != field_fit_step(config)) return;
  std::vector<float> lo, hi;
  path_bounds(lo, hi);
  // What counts as moving: the motion split's threshold (fast's 0.01 x extent where it is off).
  const double limit = (config.static_motion > 0 ? config.static_motion : 0.01) * dataset.extent;
  // An axis keeps at least 4 of the level-0 cells it had, so a flat motion still gets a grid.
  std::array<double, 3> min_size{};
  for (int k = 0; k < 3; ++k)
    min_size[k] = 4.0 * (double(aabb_max[k]) - aabb_min[k]) / std::max<uint32_t>(1, config.field_resolution[k] - 1);
  FieldBox box = fit_field_box(lo, hi, aabb_min, aabb_max, limit, min_size);
  box.at_step = iteration;

  if (box.fitted) {
    model::Checkpoint cp = snapshot(seconds);
    const deform::FieldConfig from = run::field_config(config, aabb_min, aabb_max), to = run::field_config(config, box.min, box.max);
    for (auto& [name, values] : cp.extra)
      if (name.rfind("field.planes", 0) == 0) values = deform::resample_planes(from, to, values);  // with its moments
    cp.meta["aabb_min"] = box.min, cp.meta["aabb_max"] = box.max;
    restore(cp);
  }
  facts["recipe"]["field_box"] = box.json();
  save_run_json();
  if (box.fitted) checkpoint(seconds);  // the checkpoint holds the box: a resumed run keeps it

  std::string line = "deformation field box at fine iteration " + std::to_string(iteration) + ": " + box.why;
  for (int k = 0; k < 3 && box.fitted; ++k) {
    char axis[128];
    std::snprintf(axis, sizeof axis, "%s %c [%.3g, %.3g] (was [%.3g, %.3g])", k ? "," : ";", "xyz"[k], box.min[k], box.max[k],
                  box.old_min[k], box.old_max[k]);
    line += axis;
  }
  std::cerr << line << "\n";
}

}  // namespace s4d::train
