// style4d export-ply --run RUN --time t --out F.ply: a trained run's Gaussians at time t as a
// standard 3DGS PLY for other viewers. A 4DGS run gives the deformed Gaussians (means, scales,
// rotations, opacities, SH from the heads that are on, canonical otherwise); a static run its cloud.
// The SH are cut to the degree the run renders at, so any 3DGS renderer draws what `style4d render
// --run` draws at t.
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "args.h"
#include "commands.h"
#include "run_outputs.h"
#include "s4d/engine/context.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/scene/download_cloud.h"
#include "s4d/scene/trained_run.h"
#include "s4d/splat/scene_upload.h"

namespace s4d::cli {

int cmd_export_ply(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"run", "a training run directory (style4d train)", true, "RUN"},
      {"time", "time t in [0, 1] (default 0)", true, "T"},
      {"out", "the PLY file to write", true, "F.ply"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("export-ply", "--run RUN --time T --out F.ply",
                       "Writes the run's Gaussians at time T as a standard 3DGS PLY (binary little endian):\n"
                       "for a 4DGS run the canonical Gaussians moved by the deformation field to T, for a static\n"
                       "run its Gaussians. SH coefficients are kept up to the degree the run renders at, so\n"
                       "`style4d render --ply F.ply` draws what `style4d render --run RUN` draws at T.",
                       specs);
    return 0;
  }
  const std::filesystem::path run_dir = args.require("run"), out = args.require("out");
  tools::refuse_run_output(out, run_dir, "out");
  const std::string time_text = args.get_or("time", "0");
  const double time = parse_number<double>("time", time_text);
  if (!(time >= 0 && time <= 1)) throw UsageError("--time: expected a value in [0, 1], got '" + time_text + "'");

  const scene::TrainedRun run = scene::read_trained_run(run_dir);
  engine::Context ctx;
  const std::unique_ptr<scene::SceneSource> source = scene::open_scene(ctx, run);
  // Geometry sources do not read the camera; the dataset's first view stands in for one.
  const splat::Camera camera = splat::to_splat_camera(run.dataset.views.front().camera);
  const io::GaussianCloud cloud = scene::download_cloud(ctx, source->at(time, camera));
  io::write_ply_gaussians(out, cloud);
  std::cout << "wrote " << cloud.size() << " Gaussians (" << source->describe() << ") at t = " << time << " into "
            << out.string() << "\n";
  return 0;
}

}  // namespace s4d::cli
