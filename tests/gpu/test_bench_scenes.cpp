// The rasterizer bench's scenes (bench/splat_scene.h, bench/peer_scene.h) and counts: the peer's
// scene round-trips through the project's PLY and camera readers, and the bench run on a PLY +
// transforms.json reports the tile instances and pixel-Gaussian pairs the CPU twin counts. The
// primitives' benchmark (bench/primitives_bench.h, `style4d demo`) finds the GPU sort and scan equal
// to the standard library's on one and on several blocks.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <stdexcept>
#include <string>

#include "peer_scene.h"
#include "primitives_bench.h"
#include "s4d/ref/splat_raster_ref.h"
#include "splat_bench.h"
#include "splat_scene.h"
#include "test_context.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("s4d_bench_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("the peer scene is what its description says and round-trips through the readers") {
  const bench::PeerScene peer = bench::make_peer_scene(500, 64, 48, 7);
  const io::GaussianCloud& g = peer.cloud;
  REQUIRE(g.size() == 500);
  CHECK(g.sh_degree == 3);
  for (size_t i = 0; i < g.size(); ++i) {
    const float* m = &g.means[3 * i];
    CHECK(m[0] * m[0] + m[1] * m[1] + m[2] * m[2] <= 1.0f);
    for (int k = 0; k < 3; ++k) {
      const double s = std::exp(double{g.log_scales[3 * i + k]});
      CHECK(s >= 0.01 * (1 - 1e-6));  // float logs: a relative 1e-6 either side
      CHECK(s <= 0.15 * (1 + 1e-6));
    }
  }
  REQUIRE(peer.cameras.size() == static_cast<size_t>(bench::kPeerRingCameras));
  // Camera 0 looks at the origin from kPeerRingRadius away: the origin lands on the principal point.
  const auto& w2c = peer.cameras[0].world_to_cam;
  CHECK(w2c[3] == doctest::Approx(0).epsilon(1e-12));
  CHECK(w2c[7] == doctest::Approx(0).epsilon(1e-12));
  CHECK(w2c[11] == doctest::Approx(bench::kPeerRingRadius));

  const fs::path dir = fresh_dir("peer");
  bench::write_peer_scene(dir, peer);
  const io::GaussianCloud back = io::read_ply_gaussians(dir / "points.ply");
  CHECK(back.sh_degree == g.sh_degree);
  CHECK(back.means == g.means);  // binary floats: exact
  CHECK(back.log_scales == g.log_scales);
  CHECK(back.quats == g.quats);
  CHECK(back.opacity_logits == g.opacity_logits);
  CHECK(back.sh == g.sh);
  const std::vector<io::CameraView> cams = io::read_nerf_cameras(dir / "transforms.json");
  REQUIRE(cams.size() == peer.cameras.size());
  for (size_t c = 0; c < cams.size(); ++c) {
    CHECK(cams[c].name == peer.cameras[c].name);
    CHECK(cams[c].width == 64);
    CHECK(cams[c].fx == doctest::Approx(peer.cameras[c].fx).epsilon(1e-12));
    // transforms.json stores camera-to-world in OpenGL axes: the pose comes back through an
    // inversion, exactly here (difference 0); 1e-12 leaves room for another libm.
    for (size_t k = 0; k < 16; ++k) CHECK(std::abs(cams[c].world_to_cam[k] - peer.cameras[c].world_to_cam[k]) < 1e-12);
  }
  const bench::SplatScene loaded = bench::load_splat_scene(dir / "points.ply", dir / "transforms.json", 3);
  const bench::SplatScene direct = bench::to_splat_scene(g, peer.cameras[3]);
  CHECK(loaded.gaussians.means == direct.gaussians.means);
  CHECK(loaded.gaussians.sh_degree == 3);
  for (size_t k = 0; k < 16; ++k)
    CHECK(std::abs(loaded.camera.world_to_cam[k] - direct.camera.world_to_cam[k]) < 1e-6f);  // one float ulp at 3
  CHECK_THROWS_WITH_AS(bench::load_splat_scene(dir / "points.ply", dir / "transforms.json", 8),
                       doctest::Contains("camera 8"), std::invalid_argument);
}

TEST_CASE("the bench on a PLY and a transforms.json counts what the CPU twin counts") {
  const fs::path dir = fresh_dir("counts");
  bench::write_peer_scene(dir, bench::make_peer_scene(800, 64, 48, 3));
  const bench::SplatScene scene = bench::load_splat_scene(dir / "points.ply", dir / "transforms.json", 0);
  const bench::SplatTiming t = bench::bench_splat(test::context(), scene, 2, true, true);
  CHECK(t.matches_twin);

  // The twin's counts: tile rectangles summed Gaussian by Gaussian, and per-pixel blend counts.
  const auto [proj, img] = ref::render_fwd(scene.gaussians, scene.camera, {0.0f, 0.0f, 0.0f});
  uint64_t instances = 0;
  for (size_t i = 0; i < scene.gaussians.size(); ++i) {
    const int* r = &proj.tile_rect[4 * i];
    if (proj.radius[i] > 0) instances += uint64_t(r[2] - r[0]) * uint64_t(r[3] - r[1]);
  }
  REQUIRE(instances > 1500);  // lists of tens of Gaussians per tile
  CHECK(t.instances == instances);
  CHECK(t.pixel_pairs_listed == instances * 256);
  // A pixel whose transmittance lands on the other side of the stop threshold, or an alpha on the
  // other side of 1/255, moves a pair count by one or a few: none here, 1 of 131,867 blended pairs on
  // the 1,000-Gaussian 128x128 peer scene. 1 in 10,000 (+ 1) allows for that; a Gaussian binned,
  // sorted or blended wrongly moves far more.
  const auto near = [](uint64_t gpu, uint64_t twin) {
    return (gpu > twin ? gpu - twin : twin - gpu) <= twin / 10000 + 1;
  };
  const uint64_t blended = std::accumulate(img.count.begin(), img.count.end(), uint64_t{0});
  const uint64_t evaluated = std::accumulate(img.last.begin(), img.last.end(), uint64_t{0});
  CHECK_MESSAGE(near(t.pixel_pairs_blended, blended), t.pixel_pairs_blended << " vs " << blended);
  CHECK_MESSAGE(near(t.pixel_pairs_evaluated, evaluated), t.pixel_pairs_evaluated << " vs " << evaluated);
  CHECK(t.pixel_pairs_blended <= t.pixel_pairs_evaluated);

  // Stage times over the two measured runs, within their wall time (GPU and host clocks differ:
  // 1 % + 0.5 ms; the stages added up to 74-96 % of it in three runs here).
  const engine::StageTotals& s = t.stages;
  CHECK(s.windows == 2);
  CHECK(s.stage_sum_ms() <= s.window_ms * 1.01 + 0.5);
  for (const char* stage : {"project", "sort", "raster", "backward"}) {
    const auto at = std::find(s.stages.begin(), s.stages.end(), stage);
    REQUIRE(at != s.stages.end());
    CHECK_MESSAGE(s.ms[static_cast<size_t>(at - s.stages.begin())] > 0, stage);
  }
}

TEST_CASE("the primitives' benchmark checks the GPU sort and scan against the CPU's") {
  for (uint32_t n : {1u, 1000u, 70000u}) {
    CAPTURE(n);
    const bench::PrimitiveTiming sort = bench::bench_radix_sort(test::context(), n, 1, 7);
    CHECK(sort.matches_twin);
    CHECK(sort.repeats == 1);
    const bench::PrimitiveTiming scan = bench::bench_exclusive_scan(test::context(), n, 1, 7);
    CHECK(scan.matches_twin);
  }
}
