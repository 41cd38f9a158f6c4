#include "train_plots.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/bench/line_plot.h"
#include "s4d/io/image_io.h"

namespace s4d::cli {

void write_gaussian_count_plot(const run::RunDir& run) {
  std::ifstream in(run.loss_csv());
  std::string line;
  if (!std::getline(in, line)) return;
  // The header names the column, so an older loss.csv layout is read right or refused.
  std::vector<std::string> header;
  for (std::stringstream ss(line); std::getline(ss, line, ',');) header.push_back(line);
  size_t column = header.size();
  for (size_t k = 0; k < header.size(); ++k)
    if (header[k] == "gaussians") column = k;
  if (column == header.size()) throw std::runtime_error(run.loss_csv().string() + ": no 'gaussians' column");
  bench::Series count{"Gaussians", {}};
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    for (size_t k = 0; k <= column && std::getline(ss, cell, ','); ++k)
      if (k == column) count.values.push_back(std::stod(cell));
  }
  if (count.values.empty()) return;
  io::write_png(run.root / "gaussian_count.png",
                bench::line_plot("Gaussians over training", "loss.csv row (the static stage, then the fine stage)", "Gaussians", {count}));
}

}  // namespace s4d::cli
