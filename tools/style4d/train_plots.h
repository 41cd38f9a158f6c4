// The pictures `style4d train` writes beside train.json.
#pragma once
#include <filesystem>

#include "s4d/run/run_dir.h"

namespace s4d::cli {

// RUN/gaussian_count.png: the Gaussian count at every logged step of both stages (loss.csv's
// "gaussians" column), so growth, pruning and seeding show at a glance. Nothing is written when
// loss.csv has no rows.
void write_gaussian_count_plot(const run::RunDir& run);

}  // namespace s4d::cli
