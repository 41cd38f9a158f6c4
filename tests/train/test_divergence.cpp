// The guard's diagnosis (divergence.h): which arrays of a training state hold values out of range,
// which Gaussians they sit in, whether removing those repairs it, and the one line naming them; the
// removal itself (split_state.h) and the field's part names (field_parts.h).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "host_state_fixture.h"
#include "s4d/deform/field_parts.h"
#include "s4d/model/checkpoint.h"
#include "s4d/train/divergence.h"
#include "s4d/train/split_state.h"

using namespace s4d;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

model::Checkpoint state_of(size_t n) { return {{}, test::small_state(n, 0, 7), {}}; }

}  // namespace

TEST_CASE("a state within range has no divergence, whatever its size") {
  for (size_t n : {0, 1, 40}) CHECK_FALSE(train::find_divergence(state_of(n)).found());
}

TEST_CASE("a few Gaussians out of range are named by array, count, worst value and first row, and are local") {
  model::Checkpoint cp = state_of(40);
  cp.state.cloud.quats[5 * 4 + 2] = std::numeric_limits<float>::quiet_NaN();
  cp.state.cloud.sh[9 * 3] = 1e30f, cp.state.cloud.sh[2 * 3 + 1] = -3e20f;
  const train::Divergence d = train::find_divergence(cp);
  REQUIRE(d.found());
  CHECK(d.local);
  CHECK(d.gaussians == std::vector<uint32_t>{2, 5, 9});
  CHECK_MESSAGE(contains(d.where, "'quats' of 1 Gaussian (NaN; first Gaussian 5)"), d.where);
  CHECK_MESSAGE(contains(d.where, "'sh' of 2 Gaussians (up to 1e+30; first Gaussian 2)"), d.where);
}

TEST_CASE("each array has its limit: log scales above 40, second moments above 1e30, the rest above 1e15") {
  model::Checkpoint cp = state_of(40);
  cp.state.cloud.log_scales[0] = 39.f, cp.state.cloud.log_scales[1] = -1e14f;  // a tiny Gaussian is harmless
  cp.state.v[splat::Attr::means][0] = 9e29f, cp.state.m[splat::Attr::means][0] = 9e14f;
  cp.state.cloud.means[0] = -9e14f;
  CHECK_FALSE(train::find_divergence(cp).found());
  cp.state.cloud.log_scales[3 * 3] = 41.f;
  cp.state.v[splat::Attr::opacity_logits][4] = 2e30f;
  cp.state.m[splat::Attr::means][6 * 3] = 2e15f;
  cp.state.stats[model::kGradAccum][8] = std::numeric_limits<float>::infinity();
  const train::Divergence d = train::find_divergence(cp);
  CHECK(d.gaussians == std::vector<uint32_t>{3, 4, 6, 8});
  for (const char* name : {"'log_scales' of 1 Gaussian (up to 41", "'opacity_logits.adam_v' of 1 Gaussian (up to 2e+30",
                           "'means.adam_m' of 1 Gaussian (up to 2e+15", "'grad_accum' of 1 Gaussian (inf"})
    CHECK_MESSAGE(contains(d.where, name), d.where);
}

TEST_CASE("more Gaussians than 16 or 1 %, or any field tensor, is not local; masks are not parameters") {
  CHECK(train::local_limit(100) == 16);
  CHECK(train::local_limit(5000) == 50);
  model::Checkpoint many = state_of(40);
  for (size_t g = 0; g < 17; ++g) many.state.cloud.opacity_logits[g] = 1e16f;
  const train::Divergence d = train::find_divergence(many);
  CHECK(d.gaussians.size() == 17);
  CHECK_FALSE(d.local);

  model::Checkpoint field = state_of(40);
  field.extra = {{"field.static_mask", std::vector<float>(40, 1e20f)}, {"field.planes", std::vector<float>(100, 0.1f)}};
  CHECK_FALSE(train::find_divergence(field).found());
  field.extra[1].second[42] = 1e16f, field.extra[1].second[80] = 1e17f;
  const train::Divergence f = train::find_divergence(field, [](const std::string& array, uint64_t i) {
    return array + (i < 50 ? " low" : " high");
  });
  CHECK_FALSE(f.local);
  CHECK(f.gaussians.empty());
  CHECK_MESSAGE(contains(f.where, "'field.planes' at 2 entries (up to 1e+17; in field.planes low, field.planes high)"), f.where);
}

TEST_CASE("removing Gaussians drops their rows from every array and keeps the others in order") {
  const model::HostState s = test::small_state(6, 1, 3);
  const std::vector<uint32_t> removed = {1, 4};
  const model::HostState r = train::remove_gaussians(s, removed);
  REQUIRE(r.cloud.size() == 4);
  const std::vector<size_t> kept = {0, 2, 3, 5};
  for (size_t j = 0; j < kept.size(); ++j) {
    CHECK(r.cloud.sh[j * 12] == s.cloud.sh[kept[j] * 12]);
    CHECK(r.cloud.quats[j * 4 + 3] == s.cloud.quats[kept[j] * 4 + 3]);
    CHECK(r.v[splat::Attr::means][j * 3 + 2] == s.v[splat::Attr::means][kept[j] * 3 + 2]);
    CHECK(r.stats[model::kMaxRadius][j] == s.stats[model::kMaxRadius][kept[j]]);
  }
  CHECK_THROWS_AS(train::remove_gaussians(s, std::vector<uint32_t>{6}), std::invalid_argument);
  CHECK_THROWS_AS(train::remove_gaussians(s, std::vector<uint32_t>{3, 1}), std::invalid_argument);
}

TEST_CASE("the field's part names follow its buffer layout") {
  gpu::DeformShape s{};
  s.resolution = {4, 4, 4, 3};
  s.multires = {1, 2, 0, 0};
  s.levels = 2, s.channels = 2, s.width = 8, s.trunk_extra = 0;
  s.heads = S4D_DEFORM_HEAD_POS | S4D_DEFORM_HEAD_OPACITY;
  // Level 0: xy, xz, yz hold 4 x 4 x 2 = 32 floats; xt, yt, zt 4 x 3 x 2 = 24 (order xy xz xt yz yt zt).
  CHECK(deform::plane_part(s, 0) == "level 0 plane xy");
  CHECK(deform::plane_part(s, 63) == "level 0 plane xz");
  CHECK(deform::plane_part(s, 64) == "level 0 plane xt");
  CHECK(deform::plane_part(s, gpu::deform_plane_offset(s, 1, 5)) == "level 1 plane zt");
  CHECK(deform::plane_part(s, gpu::deform_planes_total(s)) == "past the planes");
  // Trunk Linear(4 -> 8): 32 weights, 8 biases; then head pos (hidden 8 -> 8, output 8 -> 3), head opacity.
  CHECK(deform::mlp_part(s, 31) == "trunk layer 0 weight");
  CHECK(deform::mlp_part(s, 32) == "trunk layer 0 bias");
  CHECK(deform::mlp_part(s, 40) == "head pos hidden weight");
  CHECK(deform::mlp_part(s, 40 + 72) == "head pos output weight");
  CHECK(deform::mlp_part(s, 40 + 72 + 24) == "head pos output bias");
  CHECK(deform::mlp_part(s, gpu::deform_head_offset(s, 3) + 72 + 8) == "head opacity output bias");
  CHECK(deform::mlp_part(s, gpu::deform_mlp_total(s)) == "past the MLP");
}
