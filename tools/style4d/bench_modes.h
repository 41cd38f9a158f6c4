// The run mode of `style4d bench`; cmd_bench.cpp parses the options both modes share and picks it.
#pragma once
#include "args.h"
#include "s4d/bench/frames_eval.h"

namespace s4d::cli {

// --run RUN --style NAME [--style NAME2 ...] --out DIR [--spiral-frames N] [--style-image S] [--scene]
// `options` carries the shared scoring options (uiqm, warp norm, flow source and frames).
int bench_run(const Args& args, bench::FramesOptions options);

}  // namespace s4d::cli
