// Kernels nn_group_norm and nn_im2col (MUSIQ's patch stem) against their double twins on
// lavapipe: cells with a window inside, the zeros around it, ReLU, and the shapes the host refuses.
#include <doctest/doctest.h>

#include <array>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn_test_util.h"
#include "s4d/nn/group_norm.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

}  // namespace

TEST_CASE("group_norm_cells normalises each cell's window on its own and zeroes the rest, as its twin") {
  std::mt19937 rng(52);
  struct Case {
    uint32_t channels, groups, cells;
    nn::CellWindow window;
    uint32_t width;
    bool relu;
  };
  // MUSIQ's root (64 channels, 18x17 cells, 16x16 windows at (1, 1)) and bottleneck (256 channels,
  // 9x9 cells, 8x8 at (1, 1)); a window touching the cell's edges with one channel per group.
  for (const Case& k : {Case{64, 32, 5, {18, 1, 16, 1, 16}, 17, true}, Case{256, 32, 3, {9, 1, 8, 1, 8}, 9, false},
                        Case{6, 6, 2, {4, 0, 4, 2, 3}, 5, true}}) {
    auto x = test::random_chw(k.channels, k.cells * k.window.cell_h, k.width, rng, -2.0f, 2.0f);
    // An offset per cell so the statistics must be the cell's own.
    for (uint32_t c = 0; c < x.c; ++c)
      for (uint32_t y = 0; y < x.h; ++y)
        for (uint32_t i = 0; i < x.w; ++i) x.at(c, y, i) += 1.5f * float(y / k.window.cell_h);
    const auto weight = test::random_values(k.channels, 0.5f, 1.5f, rng), bias = test::random_values(k.channels, -0.3f, 0.3f, rng);
    const auto gx = test::upload(x);
    const auto norm = nn::upload_norm(context(), "gn", k.channels, weight, bias);
    const auto gpu = nn::download(
        context(), run([&](engine::Recorder& r) { return nn::group_norm_cells(r, gx, norm, k.groups, 1e-4f, k.window, k.relu); }));
    const auto twin = ref::group_norm_cells(to_double(x), to_double(weight), to_double(bias), k.groups, 1e-4, k.window.cell_h,
                                            k.window.row0, k.window.rows, k.window.col0, k.window.cols, k.relu);
    // Float sums of up to 8 x 64 values against double: measured 2.6e-7.
    INFO(k.channels << " channels, " << k.groups << " groups");
    test::expect_allclose(gpu, twin.v, {.of_largest = 1e-5}, "gpu");
    size_t zeros = 0;
    for (float v : gpu) zeros += v == 0.0f;
    const size_t outside = x.v.size() - size_t{k.cells} * k.channels * k.window.rows * k.window.cols;
    CHECK_MESSAGE(zeros >= outside, "every value outside the windows is 0");
  }
  const auto x = test::upload(test::random_chw(8, 10, 4, rng));
  const auto norm = nn::upload_norm(context(), "gn", 8, std::vector<float>(8, 1.0f), std::vector<float>(8, 0.0f));
  engine::Recorder rec(context(), "refused");
  CHECK_THROWS_AS(nn::group_norm_cells(rec, x, norm, 3, 1e-5f, {5, 0, 5, 0, 4}, false), std::invalid_argument);  // 3 groups of 8
  CHECK_THROWS_AS(nn::group_norm_cells(rec, x, norm, 4, 1e-5f, {4, 0, 4, 0, 4}, false), std::invalid_argument);  // 10 rows
  CHECK_THROWS_AS(nn::group_norm_cells(rec, x, norm, 4, 1e-5f, {5, 1, 5, 0, 4}, false), std::invalid_argument);  // window out
  CHECK_THROWS_AS(nn::group_norm_cells(rec, x, norm, 4, 1e-5f, {5, 0, 5, 1, 4}, false), std::invalid_argument);
}

// Kernel nn_im2col (MUSIQ's strided convolutions as 1x1 convolutions).
TEST_CASE("im2col unfolds as its twin, and a 1x1 convolution of it is the strided convolution") {
  std::mt19937 rng(53);
  // MUSIQ's 7x7 stride-2 root with padding 2 over two stacked patch cells, and its 9x9 stride-9
  // embedding; a 3x3 stride-1 case whose padding covers a whole row.
  for (const auto& [c, h, w, k, stride, pad] : {std::array<uint32_t, 6>{3, 74, 36, 7, 2, 2}, {5, 18, 9, 9, 9, 0}, {2, 1, 6, 3, 1, 1}}) {
    const auto x = test::random_chw(c, h, w, rng);
    const auto gx = test::upload(x);
    const auto cols = run([&](engine::Recorder& r) { return nn::im2col(r, gx, k, stride, pad); });
    const auto twin = ref::im2col(to_double(x), k, stride, pad);
    CHECK(cols.c == twin.c);
    CHECK(cols.h == twin.h);
    CHECK(cols.w == twin.w);
    INFO("a copy: exact");
    test::expect_allclose(nn::download(context(), cols), twin.v, {}, "cols");
    const uint32_t cout = 4;
    const auto params = test::random_conv(c, cout, k, rng);
    const auto as_1x1 = nn::upload_conv(context(), "unfolded", c * k * k, cout, 1, params.weight, params.bias);
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::conv1x1(r, cols, as_1x1, false); }));
    const auto conv = ref::conv2d(to_double(x), to_double(params.weight), to_double(params.bias), cout, k, stride, pad, false);
    // Float sums of up to 405 products against double: measured 4.1e-7.
    INFO(k << "x" << k << " stride " << stride);
    test::expect_allclose(gpu, conv.v, {.of_largest = 1e-5}, "gpu");
  }
  const auto small = test::upload(test::random_chw(1, 3, 3, rng));
  engine::Recorder rec(context(), "refused");
  CHECK_THROWS_AS(nn::im2col(rec, small, 7, 2, 1), std::invalid_argument);
  CHECK_THROWS_AS(nn::im2col(rec, small, 3, 0, 0), std::invalid_argument);
}
