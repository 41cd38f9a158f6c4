// style4d check-data --data DIR [--downscale N] [--json FILE]: loads a dataset as `train` would and reports
// its layout, cameras, frames, resolution, times, bounds and point cloud, then every problem found
// (s4d/data/dataset_check.h), each as "error|warning: FILE: field: message".
// Exit 0: no errors; 1: errors (printed); 2: the dataset cannot be loaded at all, or bad arguments.
#include <iostream>
#include <stdexcept>

#include "args.h"
#include "commands.h"
#include "s4d/data/dataset.h"
#include "s4d/data/dataset_check.h"
#include "s4d/util/atomic_file.h"

namespace s4d::cli {

int cmd_check_data(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"data", "the dataset directory (`check-data DIR` is the old spelling)", true, "DIR"},
      {"downscale", "integer image downscale factor, as train --downscale (default 1)", true, "N"},
      {"json", "also write the summary and the problems as JSON to FILE", true, "FILE"},
  };
  data::LoadOptions options;
  std::string json_path, dir;
  try {
    Args args(argv, specs);
    if (args.help()) {
      std::cout << usage("check-data", "--data DIR [--downscale N] [--json FILE]",
                         "Loads the dataset in DIR (DyNeRF/Neu3D frames or videos, D-NeRF, ...) as `train` does and\n"
                         "prints the layout found, cameras, frames per camera, resolution, time range, camera\n"
                         "bounds and point cloud, then every problem, one per line: 'error: FILE: field: message'\n"
                         "(or warning). Checked: image files exist (video frames within the video), image sizes\n"
                         "match their cameras, cameras face the scene, times in [0, 1], in frame order and not\n"
                         "repeated per camera, finite camera values, test views present. `train` runs the same\n"
                         "check first. Exit 0: no errors; 1: errors found; 2: the dataset cannot be loaded (the\n"
                         "loader's one-line reason) or bad arguments.",
                         specs);
      return 0;
    }
    if (args.positionals().size() > 1 || (args.get("data") && !args.positionals().empty()))
      throw UsageError("unexpected argument '" + args.positionals().back() + "'");
    if (!args.positionals().empty()) warn_deprecated("check-data DIR", "check-data --data DIR");
    if (args.positionals().empty() && !args.get("data")) throw UsageError("missing the dataset: --data DIR");
    dir = args.positionals().empty() ? *args.get("data") : args.positionals().front();
    if (auto v = args.get("downscale")) options.downscale = parse_number<int>("downscale", *v);
    if (options.downscale < 1) throw UsageError("--downscale: must be at least 1");
    json_path = args.get_or("json", "");
  } catch (const std::invalid_argument& e) {
    std::cerr << "style4d check-data: error: " << e.what() << "\n";
    return 2;
  }

  data::DatasetReport report;
  try {
    report = data::load_and_check(dir, options).report;
  } catch (const std::exception& e) {
    std::cerr << "style4d check-data: error: " << e.what() << "\n";
    return 2;
  }
  std::cout << data::format_summary(report.summary);
  for (const data::Problem& p : report.problems) std::cout << data::format_problem(p) << "\n";
  std::cout << report.errors() << (report.errors() == 1 ? " error, " : " errors, ") << report.warnings()
            << (report.warnings() == 1 ? " warning\n" : " warnings\n");
  if (!json_path.empty()) util::write_file_atomic(json_path, data::to_json(report));
  return report.errors() > 0 ? 1 : 0;
}

}  // namespace s4d::cli
