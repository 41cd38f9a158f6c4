// `s4d_bench_splat --style`: the style variant of the rasterizer against the plain one
// (style_splat_bench.cpp).
#pragma once

namespace s4d::bench {

// Parses the style bench's options (argv may hold --style itself), measures and prints; returns the
// process exit status.
int style_bench_main(int argc, char** argv);

}  // namespace s4d::bench
