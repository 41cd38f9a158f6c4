// The style kernels at lavapipe's float-atomic tile-list limit (S4D_LLVMPIPE_MAX_STYLE_LIST in
// s4d_style_splat.h): a list that long renders and differentiates every entry, so the limit is
// honest (llvmpipe would stop the loops silently, dropping the entries at the end). The fillers meet
// every pixel's cheap bound, so every batch takes both of its walks in full (raster_walk.glsl), the
// most loop iterations a list of that length can cost. Slow: 2 x 40M pairs with their MLP.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "expect_allclose.h"
#include "style_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::Cam;
using test::Scene;

constexpr std::array<float, 3> kBg = {0.3f, 0.3f, 0.3f};

}  // namespace

TEST_CASE("a tile list at the float-atomic limit renders and differentiates every entry") {
  // 32 Gaussians in front and 32 behind blend at every pixel (G > 0.8, o' = 0.1 +- 0.06: alpha in
  // [0.03, 0.16], and T stays above 1e-4); in between, fillers over the whole tile whose bound
  // (o + 0.5) G = 0.7 G > 0.5 marks them at every pixel, but whose MLP gives dO = -0.5 (opacity row
  // of W3 zero, its bias -40), so o' = -0.3 and every pixel skips them after running the MLP. If llvmpipe stopped the loops early, the forward would lose the back ones and the
  // backward (which walks back to front) the front ones; the list without fillers is the reference.
  const Cam cam = test::tile_camera();
  std::mt19937 rng(52);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  const size_t n = S4D_LLVMPIPE_MAX_STYLE_LIST, visible = 64;
  Scene g, reference;
  for (size_t i = 0; i < visible; ++i) {
    const float z = i < visible / 2 ? 2 + 0.1f * u01(rng) : 10 + 0.1f * u01(rng);
    test::add_gaussian(g, cam, 8 + 4 * u(rng), 8 + 4 * u(rng), z, 20, 0.1f, rng);
  }
  reference = g;
  for (size_t i = visible; i < n; ++i)
    test::add_gaussian(g, cam, 8 + 4 * u(rng), 8 + 4 * u(rng), 3 + 6 * u01(rng), 20, 0.2f, rng);
  ref::StyleMlp<float> mlp = test::random_mlp(n, ref::StyleDepth::relative, false, rng);
  for (size_t i = 0; i < visible; ++i)  // |dO| < 0.06: W3's opacity row and b3's opacity entry scaled down
    for (size_t c = 0; c < 5; ++c) mlp.weights[ref::kStyleMlpStride * i + S4D_STYLE_MLP_W3 + 4 * c + 3] *= 0.05f;
  for (size_t i = visible; i < n; ++i) {  // dO = sigmoid(-40) - 0.5 = -0.5
    for (size_t c = 0; c < 4; ++c) mlp.weights[ref::kStyleMlpStride * i + S4D_STYLE_MLP_W3 + 4 * c + 3] = 0;
    mlp.weights[ref::kStyleMlpStride * i + S4D_STYLE_MLP_B3 + 3] = -40;
  }
  ref::StyleMlp<float> reference_mlp = mlp;
  reference_mlp.weights.resize(ref::kStyleMlpStride * visible);

  auto run = [&](const Scene& scene, const ref::StyleMlp<float>& weights) {
    test::DeviceScene dev(test::context(), scene);
    test::DeviceStyle style(test::context(), weights);
    style.attach(dev);
    splat::Rasterizer r(test::context());
    test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);
    std::mt19937 vrng(6);
    test::GpuBackward b = test::gpu_backward(r, dev, test::random_cotangents(cam, vrng, true), 256);
    return std::tuple(std::move(f), std::move(b), style.download_v_mlp(test::context()));
  };
  const auto [f, b, v_mlp] = run(g, mlp);
  const auto [rf, rb, rv_mlp] = run(reference, reference_mlp);
  REQUIRE(f.longest_tile_list == n);
  CHECK(f.img.count == rf.img.count);  // exact: the fillers are skipped, the rest blend in the same order
  CHECK(f.img.rgb == rf.img.rgb);
  CHECK(*std::min_element(f.img.count.begin(), f.img.count.end()) == static_cast<int>(visible));
  std::vector<float> head(v_mlp.begin(), v_mlp.begin() + static_cast<long>(reference_mlp.weights.size()));
  test::expect_allclose(head, rv_mlp, {.of_largest = 1e-6}, "head");  // the same subgroup sums in the same order; measured 0
  std::vector<float> means(b.grads.v_means.begin(), b.grads.v_means.begin() + 3 * visible);
  test::expect_allclose(means, rb.grads.v_means, {.of_largest = 1e-6}, "means");  // measured 0
  // Exact: the fillers never blend.
  CHECK(std::all_of(v_mlp.begin() + static_cast<long>(head.size()), v_mlp.end(), [](float x) { return x == 0.0f; }));
}
