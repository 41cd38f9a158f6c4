// A trained run for the viewer's tests, made once per test process: the built-in synthetic scene
// (4 cameras, 3 frames, 64x48) trained 100 iterations of the fast preset's static stage on the first
// frame.
#pragma once
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "cli_run.h"

namespace s4d::test {

inline const std::filesystem::path& trained_run() {
  static const std::filesystem::path run = [] {
    const std::filesystem::path dir = fresh_dir("view_fixture");
    const std::string data = (dir / "data").string(), run_dir = (dir / "run").string();
    REQUIRE(run_style4d("synth", "--out " + data + " --cams 4 --frames 3 --size 64x48", dir / "synth.log") == 0);
    REQUIRE_MESSAGE(run_style4d("train", "--data " + data + " --out " + run_dir + " --preset fast --iters 100 --max-time 0 --stage static",
                                dir / "train.log") == 0,
                    read_text(dir / "train.log"));
    return std::filesystem::path(run_dir);
  }();
  return run;
}

}  // namespace s4d::test
