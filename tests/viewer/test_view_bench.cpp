// s4d_bench_viewer --run: the moving-camera bench orbits a trained run at full resolution and at
// the adaptive scale and prints both and their ratio (its timings are never checked).
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "view_fixture.h"

namespace fs = std::filesystem;
using s4d::test::read_text;

TEST_CASE("the moving-camera bench orbits a run at full resolution and at the adaptive scale") {
  const fs::path run = s4d::test::trained_run();
  const fs::path dir = s4d::test::fresh_dir("view_bench");
  // A budget no frame meets: every moving frame of the adaptive orbit renders at the floor, 1/4.
  const std::string cmd = std::string(S4D_BENCH_VIEWER_EXE) + " --run " + run.string() +
                          " --orbit 3 --size 64x48 --frame-budget-ms 0.001 --repeats 1 > " +
                          (dir / "bench.jsonl").string() + " 2> " + (dir / "bench.log").string();
  REQUIRE_MESSAGE(std::system(cmd.c_str()) == 0, read_text(dir / "bench.log"));
  const std::string lines = read_text(dir / "bench.jsonl");
  // nlohmann::json dumps keys in order: "mean_scale" comes right before "mode".
  CHECK_MESSAGE(lines.find("\"mean_scale\":1.0,\"mode\":\"full\"") != std::string::npos, lines);
  CHECK_MESSAGE(lines.find("\"mean_scale\":0.25,\"mode\":\"adaptive\"") != std::string::npos, lines);
  CHECK_MESSAGE(lines.find("\"bench\":\"viewer_orbit_ratio\"") != std::string::npos, lines);
  // A bad option names itself.
  const std::string bad = std::string(S4D_BENCH_VIEWER_EXE) + " --run " + run.string() + " --orbit 0 2> " +
                          (dir / "bad.log").string();
  CHECK(std::system(bad.c_str()) != 0);
  CHECK(read_text(dir / "bad.log").find("--orbit") != std::string::npos);
}
