// `style4d export-ply`: a 4DGS run's deformed Gaussians at time t, rendered by `style4d render --ply`
// (any 3DGS renderer), give what `render --run` gives at t; runs missing the 4DGS stage's files are
// refused naming the file and what is missing.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "run4d_fixture.h"
#include "s4d/data/dataset.h"
#include "s4d/io/image_io.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/model/checkpoint.h"

namespace fs = std::filesystem;
using s4d::test::max_abs_diff;
using s4d::test::read_text;
using s4d::test::run_style4d;

TEST_CASE("export-ply at t rendered with render --ply matches render --run at t") {
  const s4d::test::Run4d& r = s4d::test::run4d();
  const fs::path dir = s4d::test::fresh_dir("export_ply_4d");
  const s4d::data::Dataset d = s4d::data::load_dataset(r.data);
  s4d::io::CameraView cam = d.views.front().camera;  // cam00, the test camera
  REQUIRE(d.views.front().name.rfind("cam00", 0) == 0);
  cam.file_path = "./cam";
  s4d::io::write_nerf_cameras(dir / "transforms.json", {cam});

  const fs::path protocol = dir / "protocol";
  REQUIRE(run_style4d("render", "--run " + r.run.string() + " --path test --out " + protocol.string(), dir / "run.log") == 0);
  for (const auto& [time, k] : {std::pair{"0", 0}, {"0.5", 1}, {"1", 2}}) {
    const fs::path ply = dir / ("t" + std::to_string(k) + ".ply"), out = dir / ("ply" + std::to_string(k));
    REQUIRE_MESSAGE(run_style4d("export-ply", "--run " + r.run.string() + " --time " + time + " --out " + ply.string(),
                                dir / "export.log") == 0,
                    read_text(dir / "export.log"));
    REQUIRE_MESSAGE(run_style4d("render", "--ply " + ply.string() + " --cameras " + (dir / "transforms.json").string() +
                                              " --out " + out.string() + " --background " +
                                              s4d::test::background_arg(d.background),
                                dir / "ply.log") == 0,
                    read_text(dir / "ply.log"));
    const s4d::io::ImageF from_ply = s4d::io::read_png(out / "cam.png");
    const s4d::io::ImageF from_run = s4d::io::read_png(protocol / "cam00" / s4d::test::png_name("000", k));
    // The PLY holds the deformed float32 values bit for bit and the SH cut to the run's degree, so
    // both paths rasterize the same numbers; only the 8-bit rounding may differ by a level.
    // Measured worst case on lavapipe (Mesa 22.3.6, LLVM 15): 0 levels; allowed: 1 level.
    CHECK_MESSAGE(max_abs_diff(from_ply, from_run) <= 1.0f / 255.0f + 1e-6f, "t = " << time);
  }
  // The deformation moves the Gaussians: the clouds at t = 0 and t = 1 differ.
  const s4d::io::GaussianCloud c0 = s4d::io::read_ply_gaussians(dir / "t0.ply"), c1 = s4d::io::read_ply_gaussians(dir / "t2.ply");
  REQUIRE(c0.size() == c1.size());
  CHECK(c0.means != c1.means);
}

TEST_CASE("a 4DGS run without its checkpoint, or whose checkpoint lacks the field or the 4DGS stage, is refused") {
  const s4d::test::Run4d& r = s4d::test::run4d();
  const fs::path dir = s4d::test::fresh_dir("run4d_errors");
  const fs::path partial = dir / "partial", ckpt = partial / "checkpoint" / "state.s4dckpt";
  fs::create_directories(partial / "checkpoint");
  fs::copy(r.run / "geometry", partial / "geometry");
  fs::copy_file(r.run / "run.json", partial / "run.json");
  auto all_fail_with = [&](const std::string& message) {
    const std::string run = partial.string();
    for (const auto& [command, args] :
         {std::pair<std::string, std::string>{"render", "--run " + run + " --path test --out " + (dir / "out").string()},
          {"view", run + " --screenshot " + (dir / "x.png").string()},
          {"export-ply", "--run " + run + " --out " + (dir / "x.ply").string()}}) {
      CHECK(run_style4d(command, args, dir / "log") != 0);
      const std::string log = read_text(dir / "log");
      CHECK_MESSAGE(log.find(message) != std::string::npos, command << ": " << log);
    }
    CHECK(!fs::exists(dir / "out"));
    CHECK(!fs::exists(dir / "x.png"));
    CHECK(!fs::exists(dir / "x.ply"));
  };
  all_fail_with(ckpt.string() + ": missing (the canonical Gaussians and the deformation field");
  CHECK(read_text(dir / "log").find("incomplete run") != std::string::npos);
  CHECK(read_text(dir / "log").find("style4d train --run " + partial.string()) != std::string::npos);

  s4d::model::Checkpoint cp = s4d::model::read_checkpoint(r.run / "checkpoint" / "state.s4dckpt");
  s4d::model::Checkpoint no_field = cp;
  std::erase_if(no_field.extra, [](const auto& a) { return a.first == "field.planes"; });
  s4d::model::write_checkpoint(ckpt, no_field);
  all_fail_with(ckpt.string() + ": no array 'field.planes'");

  s4d::model::Checkpoint static_stage = cp;
  static_stage.meta["stage"] = "static";
  static_stage.meta["iteration"] = 20;
  s4d::model::write_checkpoint(ckpt, static_stage);
  all_fail_with(ckpt.string() + ": the run is incomplete: the checkpoint is from the static stage (iteration 20 of 40)");
  CHECK(read_text(dir / "log").find("style4d train --run " + partial.string()) != std::string::npos);
}
