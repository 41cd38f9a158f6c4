// The run mode of `style4d bench`; cmd_bench.cpp parses the options both modes share and picks it.
#pragma once
#include "args.h"
#include <optional>

#include "s4d/bench/frames_eval.h"
#include "s4d/bench/native_learned.h"
#include "s4d/bench/pyiqa_bridge.h"

namespace s4d::cli {

// --run RUN --style NAME [--style NAME2 ...] --out DIR [--spiral-frames N] [--style-image S] [--scene]
// `options` carries the shared scoring options (uiqm, warp norm, flow source and frames).
int bench_run(const Args& args, bench::FramesOptions options);

// --python PY, --bridge-script FILE and --bridge-metrics LIST, the bridge working in OUT/bridge,
// less the keys `learned` computes natively; nullopt without --python or with no key left.
std::optional<bench::BridgeOptions> bridge_options(const Args& args, const std::filesystem::path& out,
                                                   const bench::NativeLearned* learned);

// --metric-weights DIR and --gram-vgg; nullopt without --metric-weights.
std::optional<bench::NativeLearnedOptions> learned_options(const Args& args);

}  // namespace s4d::cli
