// A 4DGS run for the tests of rendering, exporting and viewing one, made once per test process: the
// built-in synthetic scene (4 cameras, 3 frames at t = 0, 0.5, 1; 48x36) trained 40 static and 120
// fine iterations of the fast preset, one view per fine step (about 65 s on lavapipe, 2 cores). 30
// fine iterations barely start the motion (renders at t = 0 and 1 differ by at most 3 levels, about
// as much where the scene moves as where it stays); 120 make the motion visible where it happens.
// --static-motion 0.002 leaves some Gaussians out of the field (measured 1261 of 4000), so renders
// of the run must apply the checkpoint's still mask to match the trainer's own evaluation.
// Plus the helpers those tests share.
#pragma once
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "max_abs_diff.h"
#include "cli_run.h"
#include "s4d/io/image_io.h"

namespace s4d::test {

struct Run4d {
  std::filesystem::path root, data, run;
};

inline const Run4d& run4d() {
  static const Run4d r = [] {
    const std::filesystem::path dir = fresh_dir("run4d_fixture");
    Run4d out{dir, dir / "data", dir / "run"};
    REQUIRE(run_style4d("synth", "--out " + out.data.string() + " --cams 4 --frames 3 --size 48x36", dir / "synth.log") == 0);
    REQUIRE_MESSAGE(run_style4d("train", "--data " + out.data.string() + " --out " + out.run.string() +
                                             " --preset fast --iters 40 --fine-iters 120 --batch 1 --static-motion 0.002",
                                dir / "train.log") == 0,
                    read_text(dir / "train.log"));
    return out;
  }();
  return r;
}

// PREFIX + k + ".png": frame files (prefix "000" gives the protocol's 000K.png for the fixture's
// three frames).
inline std::string png_name(const std::string& prefix, int k) { return prefix + std::to_string(k) + ".png"; }

// "r,g,b" for --background.
inline std::string background_arg(const std::array<float, 3>& bg) {
  std::ostringstream s;
  s.precision(9);
  s << bg[0] << "," << bg[1] << "," << bg[2];
  return s.str();
}

}  // namespace s4d::test
