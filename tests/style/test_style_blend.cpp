// The blend of two styles (training/runs/scene/style_blend.h) on hand-made style files: the ends are
// each style exactly, colours and opacities lerp, MLP weights lerp with the hidden layers of an MLP
// that adds nothing taken from the other style, and the refusals name what is wrong.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>

#include "s4d/scene/style_blend.h"
#include "s4d_style_splat.h"

namespace {

using namespace s4d;

constexpr uint32_t kCount = 3, kCoeffs = 4;

// A style whose every array value is distinct and depends on `base`.
run::StyleFile sample(run::StyleMethod method, float base) {
  run::StyleFile s;
  s.method = method;
  s.settings = {{"seed", 0}, {"mlp_init", "identity"}};
  s.count = kCount, s.sh_coeffs = kCoeffs;
  for (uint32_t k = 0; k < kCount * kCoeffs * 3; ++k) s.sh_delta.push_back(base + 0.01f * static_cast<float>(k));
  for (uint32_t k = 0; k < kCount; ++k) s.opacity_delta.push_back(-base + 0.1f * static_cast<float>(k));
  if (method == run::StyleMethod::full)
    for (uint32_t k = 0; k < kCount * S4D_STYLE_MLP_STRIDE; ++k) s.mlp.push_back(base - 0.003f * static_cast<float>(k));
  s.depth_input = run::DepthInput::relative, s.depth_scale = 2.0f, s.input_sigmoid = false;
  return s;
}

std::string refusal(const run::StyleFile& a, const run::StyleFile& b, float alpha) {
  try {
    scene::blend_styles(a, b, alpha);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a blend at 0 is its first style, at 1 its second, exactly, and lerps every array between") {
  const run::StyleFile a = sample(run::StyleMethod::full, 0.3f), b = sample(run::StyleMethod::full, -0.7f);
  const run::StyleFile at0 = scene::blend_styles(a, b, 0.0f), at1 = scene::blend_styles(a, b, 1.0f);
  CHECK(at0.sh_delta == a.sh_delta);
  CHECK(at0.opacity_delta == a.opacity_delta);
  CHECK(at0.mlp == a.mlp);
  CHECK(at1.sh_delta == b.sh_delta);
  CHECK(at1.opacity_delta == b.opacity_delta);
  CHECK(at1.mlp == b.mlp);
  const run::StyleFile mid = scene::blend_styles(a, b, 0.25f);
  CHECK(mid.method == run::StyleMethod::full);
  CHECK(mid.count == kCount);
  CHECK(mid.depth_scale == a.depth_scale);
  for (size_t k = 0; k < mid.mlp.size(); ++k) CHECK(mid.mlp[k] == doctest::Approx(0.75 * a.mlp[k] + 0.25 * b.mlp[k]));
  for (size_t k = 0; k < mid.sh_delta.size(); ++k)
    CHECK(mid.sh_delta[k] == doctest::Approx(0.75 * a.sh_delta[k] + 0.25 * b.sh_delta[k]));
  CHECK(mid.opacity_delta[2] == doctest::Approx(0.75 * a.opacity_delta[2] + 0.25 * b.opacity_delta[2]));
}

TEST_CASE("an MLP that adds nothing blends as the other style's with its last layer scaled") {
  const run::StyleFile colors = sample(run::StyleMethod::colors, 0.2f), full = sample(run::StyleMethod::full, 0.5f);
  const run::StyleFile mid = scene::blend_styles(colors, full, 0.4f);
  CHECK(mid.method == run::StyleMethod::full);
  for (size_t k = 0; k < mid.mlp.size(); ++k) {
    const bool last = k % S4D_STYLE_MLP_STRIDE >= S4D_STYLE_MLP_W3;
    CHECK(mid.mlp[k] == doctest::Approx(last ? 0.4 * full.mlp[k] : full.mlp[k]));
  }
  CHECK(scene::blend_styles(colors, sample(run::StyleMethod::colors, 0.9f), 0.5f).mlp.empty());

  // Per Gaussian: Gaussian 1 of `region` adds nothing (outside a --region), the others are trained.
  run::StyleFile region = sample(run::StyleMethod::full, -0.1f);
  std::fill_n(region.mlp.begin() + S4D_STYLE_MLP_STRIDE, S4D_STYLE_MLP_STRIDE, 0.0f);
  const run::StyleFile r = scene::blend_styles(region, full, 0.5f);
  for (uint32_t k = 0; k < S4D_STYLE_MLP_STRIDE; ++k) {
    const size_t g1 = S4D_STYLE_MLP_STRIDE + k;
    CHECK(r.mlp[g1] == doctest::Approx(k >= S4D_STYLE_MLP_W3 ? 0.5 * full.mlp[g1] : full.mlp[g1]));
    CHECK(r.mlp[k] == doctest::Approx(0.5 * region.mlp[k] + 0.5 * full.mlp[k]));  // Gaussian 0: both trained
  }
}

TEST_CASE("blending with the original scene scales a style's changes") {
  const run::StyleFile full = sample(run::StyleMethod::full, 0.5f), none = scene::no_style(kCount, kCoeffs);
  const run::StyleFile third = scene::blend_styles(none, full, 1.0f / 3.0f);
  for (size_t k = 0; k < full.sh_delta.size(); ++k) CHECK(third.sh_delta[k] == doctest::Approx(full.sh_delta[k] / 3.0));
  CHECK(scene::blend_styles(full, none, 1.0f).sh_delta == none.sh_delta);
}

TEST_CASE("blends are refused for a factor outside [0, 1], scratch styles, other sizes, initialisations or inputs") {
  const run::StyleFile a = sample(run::StyleMethod::full, 0.3f), b = sample(run::StyleMethod::full, -0.7f);
  for (float alpha : {-0.01f, 1.01f, std::numeric_limits<float>::quiet_NaN()})
    CHECK(refusal(a, b, alpha).find("is not in [0, 1]") != std::string::npos);
  run::StyleFile scratch;
  scratch.method = run::StyleMethod::scratch;
  CHECK(refusal(a, scratch, 0.5f).find("--method scratch") != std::string::npos);
  run::StyleFile fewer = sample(run::StyleMethod::colors, 0.1f);
  fewer.count = 2, fewer.sh_delta.resize(2 * kCoeffs * 3), fewer.opacity_delta.resize(2);
  CHECK(refusal(a, fewer, 0.5f).find("trained for 3 and 2 Gaussians") != std::string::npos);
  run::StyleFile degree = sample(run::StyleMethod::colors, 0.1f);
  degree.sh_coeffs = 1, degree.sh_delta.resize(kCount * 3);
  CHECK(refusal(a, degree, 0.5f).find("4 and 1 SH coefficients") != std::string::npos);
  run::StyleFile seed = b;
  seed.settings["seed"] = 7;
  CHECK(refusal(a, seed, 0.5f).find("other initialisations (seed 0 and 7)") != std::string::npos);
  run::StyleFile uniform = b;
  uniform.settings["mlp_init"] = "uniform";
  CHECK(refusal(a, uniform, 0.5f).find("mlp_init") != std::string::npos);
  run::StyleFile depth = b;
  depth.depth_scale = 3.0f;
  CHECK(refusal(a, depth, 0.5f).find("read other inputs") != std::string::npos);
  CHECK(refusal(sample(run::StyleMethod::colors, 0.1f), seed, 0.5f).empty());  // one MLP: nothing to match
}
