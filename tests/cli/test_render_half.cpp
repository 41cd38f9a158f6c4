// `style4d render --half` of the shared 4DGS run (run4d_fixture.h) and of a style of it with MLPs
// (style_fixture.h): the SH and the style MLPs' weights held on the device as halves render within
// a measured bound of the float render, and render.json reports their storage at half the bytes.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "style_fixture.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

double max_diff(const std::vector<float>& a, const std::vector<float>& b) {
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(static_cast<double>(a[k]) - b[k]));
  return worst;
}

// render.json's "storage" of the render tagged `tag` (test::render_test_path's folder).
nlohmann::json storage_of(const std::string& tag) {
  return nlohmann::json::parse(test::read_text(test::run4d().root / ("render_" + tag) / "render.json"))["storage"];
}

// The half storage's bytes (f16) against the float storage's (f32): at most half (a half is 2
// bytes; packed buffers end on whole 4-byte words), and less device memory at the peak. Returns
// both byte counts.
std::pair<uint64_t, uint64_t> check_halved(const nlohmann::json& f32, const nlohmann::json& f16) {
  CHECK(f32["precision"] == "f32");
  CHECK(f16["precision"] == "f16");
  const uint64_t full = f32["sh_style_bytes"].get<uint64_t>(), half = f16["sh_style_bytes"].get<uint64_t>();
  CHECK(full > 0);
  CHECK(half * 2 <= full + 16);  // at most one padded word for each of four buffers
  CHECK(f16["device_memory_peak_bytes"].get<uint64_t>() < f32["device_memory_peak_bytes"].get<uint64_t>());
  return {full, half};
}

}  // namespace

// Rounding each SH coefficient to a half moves it by at most 2^-11 of itself, and the colour by a
// small multiple of that. Measured worst RGB difference over the three test frames (lavapipe, Mesa
// 22.3.6): 8.2e-5; allowed: 1e-3 (12x; a quarter of an 8-bit level).
TEST_CASE("render --half of a 4DGS run stays within a measured bound of the float render at half the SH bytes") {
  const std::vector<float> full = test::rgb_exr("", "half_f32"), half = test::rgb_exr("--half", "half_f16");
  MESSAGE("SH half against float, max |diff| " << max_diff(half, full));
  CHECK(max_diff(half, full) <= 1e-3);
  CHECK(half != full);  // the halves round: not the float path by accident
  const auto [f32_bytes, f16_bytes] = check_halved(storage_of("half_f32"), storage_of("half_f16"));
  CHECK(f16_bytes * 2 >= f32_bytes);  // the canonical SH are all it holds: exactly half, up to padding
}

// A style with MLPs: its SH (the run's plus the style's delta, packed once) and its MLP weights as
// halves (the float storage also holds the delta and the run's SH, so half storage takes less than
// half). The weights' rounding passes through the MLP's sigmoids. Measured worst RGB difference
// (lavapipe, Mesa 22.3.6): 2.0e-4; allowed: 2e-3 (10x; half an 8-bit level).
TEST_CASE("render --half of a style holds its SH and MLP weights as halves within a measured bound of the float render") {
  test::styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  const std::vector<float> full = test::rgb_exr("--style full", "half_style_f32");
  const std::vector<float> half = test::rgb_exr("--style full --half", "half_style_f16");
  MESSAGE("style half against float, max |diff| " << max_diff(half, full));
  CHECK(max_diff(half, full) <= 2e-3);
  CHECK(half != full);
  check_halved(storage_of("half_style_f32"), storage_of("half_style_f16"));
}
