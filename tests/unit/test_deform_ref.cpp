// CPU twin of the deformation field (hexplane_ref.h, deform_mlp_ref.h, deform_ref.h,
// hexplane_reg_ref.h): layouts, the 4DGaussians coordinate mapping, every gradient against central
// finite differences in double with random cotangents, and the initialisation (field_init.h).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/deform/field_config.h"
#include "s4d/deform/field_init.h"
#include "s4d/deform/field_resample.h"
#include "s4d/ref/deform_ref.h"
#include "s4d/ref/hexplane_reg_ref.h"
#include "s4d/ref/random_deform.h"

namespace {

using namespace s4d;

deform::FieldConfig small_config() {
  deform::FieldConfig c;
  c.resolution = {5, 4, 6, 5};
  c.multires = {1, 2};
  c.channels = 3;
  c.width = 6;
  c.trunk_extra = 1;
  c.heads = S4D_DEFORM_HEADS_DYNERF;
  c.aabb_min = {-1.0f, -0.5f, 0.0f};
  c.aabb_max = {1.0f, 1.5f, 2.0f};
  return c;
}

// A field with planes around 1 (so the 6-fold products stay O(1)) and xavier-scale weights.
ref::DeformField<double> random_field(const deform::FieldConfig& c, unsigned seed) {
  std::mt19937 rng(seed);
  ref::DeformField<double> f;
  f.shape = deform::deform_shape(c);
  for (int k = 0; k < 3; ++k) {
    f.aabb_max[k] = c.aabb_max[k];
    f.aabb_scale[k] = 2.0 / (c.aabb_min[k] - c.aabb_max[k]);
  }
  f.planes = ref::uniform<double>(gpu::deform_planes_total(f.shape), rng, 0.5, 1.5);
  f.mlp = ref::uniform<double>(gpu::deform_mlp_total(f.shape), rng, -0.6, 0.6);
  return f;
}

ref::DeformGaussians<double> random_gaussians(const deform::FieldConfig& c, size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  ref::DeformGaussians<double> g =
      ref::random_gaussians<double>(c.aabb_min, c.aabb_max, n, rng, {.margin = 0.05, .sh_coeffs = S4D_DEFORM_SH_COEFFS});
  g.still_mask.assign(n, 0);
  g.still_mask[1] = 1;  // one still Gaussian: no field term, pure pass-through
  return g;
}

// sum of v . deformed over every output array.
double weighted(const ref::DeformGaussians<double>& out, const ref::DeformGaussians<double>& v) {
  double sum = 0;
  auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    for (size_t k = 0; k < a.size(); ++k) sum += a[k] * b[k];
  };
  dot(out.means, v.means), dot(out.log_scales, v.log_scales), dot(out.quats, v.quats);
  dot(out.opacity_logits, v.opacity_logits), dot(out.sh, v.sh);
  return sum;
}

// Largest |central difference - analytic| over the entries of `x`, relative to the largest |analytic|.
double fd_worst(std::vector<double>& x, const std::vector<double>& analytic, const std::function<double()>& loss) {
  double worst = 0, scale = 1e-30;
  for (size_t k = 0; k < x.size(); ++k) {
    const double saved = x[k], h = 1e-6 * std::max(1.0, std::abs(saved));
    x[k] = saved + h;
    const double lp = loss();
    x[k] = saved - h;
    const double lm = loss();
    x[k] = saved;
    worst = std::max(worst, std::abs((lp - lm) / (2 * h) - analytic[k]));
    scale = std::max(scale, std::abs(analytic[k]));
  }
  return worst / scale;
}

}  // namespace

TEST_CASE("deformation layouts: plane axes in 4DGaussians' order, contiguous plane and MLP offsets") {
  const uint32_t u[6] = {0, 0, 0, 1, 1, 2}, v[6] = {1, 2, 3, 2, 3, 3};  // xy, xz, xt, yz, yt, zt
  for (uint32_t p = 0; p < 6; ++p) {
    CHECK(S4D_DEFORM_PLANE_AXIS_U(p) == u[p]);
    CHECK(S4D_DEFORM_PLANE_AXIS_V(p) == v[p]);
  }
  const gpu::DeformShape s = deform::deform_shape(small_config());
  CHECK(gpu::deform_axis_res(s, 1, 0) == 10);
  CHECK(gpu::deform_axis_res(s, 1, 3) == 5);  // time is not multiplied
  uint32_t expected = 0;
  for (uint32_t l = 0; l < s.levels; ++l)
    for (uint32_t p = 0; p < 6; ++p) {
      CHECK(gpu::deform_plane_offset(s, l, p) == expected);
      expected += gpu::deform_axis_res(s, l, u[p]) * gpu::deform_axis_res(s, l, v[p]) * s.channels;
    }
  CHECK(gpu::deform_planes_total(s) == expected);
  // MLP: trunk 6 -> 6 (+ bias), one extra 6 -> 6, then each head 6 -> 6 -> out.
  CHECK(gpu::deform_trunk_offset(s, 1) == 42);
  CHECK(gpu::deform_head_offset(s, 0) == 84);
  CHECK(gpu::deform_head_offset(s, 1) == 84 + 42 + 21);
  CHECK(gpu::deform_mlp_total(s) == 84 + 5 * 42 + 7 * (3 + 3 + 4 + 1 + 48));
  gpu::DeformShape no_scales = s;
  no_scales.heads = S4D_DEFORM_HEADS_DYNERF & ~S4D_DEFORM_HEAD_SCALES;
  CHECK(gpu::deform_head_offset(no_scales, 2) == gpu::deform_head_offset(no_scales, 1));  // a head that is off takes no room
}

TEST_CASE("scratch rows: features, activations, cotangents and head outputs tile the row, each layer reads its own") {
  const gpu::DeformShape s = deform::deform_shape(small_config());  // F = W = 6, one extra trunk layer, five heads
  gpu::DeformShape dnerf = s;
  dnerf.heads = S4D_DEFORM_HEADS_DNERF;
  dnerf.trunk_extra = 0;
  CHECK(gpu::deform_scratch_floats(s) == 6 + 2 * 7 * 6 + 59 + 6);  // feat, 7 slots x (act, cot), head outs, v_feat
  for (const gpu::DeformShape& shape : {s, dnerf}) {
    const uint32_t F = gpu::deform_feat_dim(shape), W = shape.width, te = shape.trunk_extra;
    std::vector<int> cover(gpu::deform_scratch_floats(shape), 0);
    auto mark = [&](uint32_t col, uint32_t n) {
      REQUIRE(col + n <= cover.size());
      for (uint32_t k = 0; k < n; ++k) ++cover[col + k];
    };
    mark(0, F);
    for (uint32_t slot = 0; slot < gpu::deform_slots(shape); ++slot) {
      mark(gpu::deform_act_col(shape, slot), W);
      mark(gpu::deform_cot_col(shape, slot), W);
    }
    for (uint32_t l = te + 2; l < gpu::deform_layer_count(shape); l += 2) mark(gpu::deform_v_out_col(shape, l), gpu::deform_layer_out(shape, l));
    mark(gpu::deform_v_feat_col(shape), F);
    CHECK(std::all_of(cover.begin(), cover.end(), [](int c) { return c == 1; }));
    // A layer's input is its producer's activation, and dL/d input its producer's cotangent.
    CHECK(gpu::deform_in_col(shape, 0) == 0);
    CHECK(gpu::deform_v_in_col(shape, 0) == gpu::deform_v_feat_col(shape));
    for (uint32_t l = 1; l < gpu::deform_layer_count(shape); ++l) {
      CAPTURE(l);
      const uint32_t producer = l <= te ? l - 1 : gpu::deform_layer_is_head_out(shape, l) ? l - 1 : te;
      CHECK(gpu::deform_in_col(shape, l) == gpu::deform_act_col(shape, gpu::deform_out_slot(shape, producer)));
      CHECK(gpu::deform_v_in_col(shape, l) == gpu::deform_v_out_col(shape, producer));
    }
  }
}

TEST_CASE("deformation config errors name the field") {
  auto message = [](deform::FieldConfig c) {
    try {
      deform::deform_shape(c);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  deform::FieldConfig c = small_config();
  c.resolution[3] = 2;
  CHECK(message(c).find("resolution.t") != std::string::npos);
  c = small_config();
  c.width = 129;
  CHECK(message(c).find("width") != std::string::npos);
  c = small_config();
  c.aabb_max[1] = c.aabb_min[1];
  CHECK(message(c).find("aabb_max.y") != std::string::npos);
  c = small_config();
  c.multires = {1, 2, 3, 4, 5};
  CHECK(message(c).find("multires") != std::string::npos);
}

TEST_CASE("hexplane lookup follows 4DGaussians: mirrored AABB, unnormalised time on align_corners texels") {
  deform::FieldConfig c = small_config();
  c.multires = {1};
  c.channels = 1;
  ref::DeformField<double> f = random_field(c, 1);
  // Every plane 1, except xy = its x texel index and xt = its t texel index: feature = i_x * i_t.
  std::fill(f.planes.begin(), f.planes.end(), 1.0);
  const uint32_t rx = c.resolution[0], ry = c.resolution[1], rt = c.resolution[3];
  for (uint32_t y = 0; y < ry; ++y)
    for (uint32_t x = 0; x < rx; ++x) f.planes[gpu::deform_plane_offset(f.shape, 0, 0) + y * rx + x] = x;
  for (uint32_t t = 0; t < rt; ++t)
    for (uint32_t x = 0; x < rx; ++x) f.planes[gpu::deform_plane_offset(f.shape, 0, 2) + t * rx + x] = x == 0 ? t : 1.0;
  // x = aabb_max maps to -1, texel 0 (the xt plane then reads column 0, its t index).
  const double at_max[3] = {1.0, 0.5, 1.0}, at_min[3] = {-1.0, 0.5, 1.0};
  CHECK(ref::hexplane_features(f, at_min, 0.0)[0] == doctest::Approx(rx - 1));     // x = min: texel R - 1, xt column reads 1
  CHECK(ref::hexplane_features(f, at_max, 0.0)[0] == doctest::Approx(0.0));        // texel 0 of xy
  for (uint32_t y = 0; y < ry; ++y) f.planes[gpu::deform_plane_offset(f.shape, 0, 0) + y * rx] = 1.0;  // feature = t index
  CHECK(ref::hexplane_features(f, at_max, 0.0)[0] == doctest::Approx((rt - 1) / 2.0));  // t = 0: middle of the axis
  CHECK(ref::hexplane_features(f, at_max, 1.0)[0] == doctest::Approx(rt - 1.0));        // t = 1: last texel
  CHECK(ref::hexplane_features(f, at_max, 0.5)[0] == doctest::Approx(0.75 * (rt - 1)));
  CHECK(ref::hexplane_features(f, at_max, 7.0)[0] == doctest::Approx(rt - 1.0));        // border clamp
}

TEST_CASE("the time axis's range: grid_time maps it onto [-1, 1], and 4DGaussians' {-1, 1} is the time itself") {
  deform::FieldConfig c = small_config();
  for (double t : {0.0, 1e-30, 0.123456789, 1.0, -3.5, 1e30}) CHECK(deform::grid_time(c, t) == static_cast<float>(t));
  c.time_range = {0, 1};
  CHECK(deform::grid_time(c, 0.0) == -1.0f);
  CHECK(deform::grid_time(c, 0.5) == 0.0f);
  CHECK(deform::grid_time(c, 1.0) == 1.0f);
  CHECK(deform::grid_time(c, 0.25) == -0.5f);
  c.time_range = {0.5, 0.5};
  CHECK_THROWS_WITH_AS(deform::deform_shape(c), doctest::Contains("time_range"), std::invalid_argument);
  c.time_range = {0, NAN};
  CHECK_THROWS_WITH_AS(deform::deform_shape(c), doctest::Contains("time_range"), std::invalid_argument);
}

TEST_CASE("deform twin backward matches central finite differences in double") {
  const deform::FieldConfig c = small_config();
  ref::DeformField<double> f = random_field(c, 2);
  ref::DeformGaussians<double> g = random_gaussians(c, 6, 3);
  std::mt19937 rng(4);
  ref::DeformGaussians<double> v;
  v.means = ref::uniform<double>(g.means.size(), rng, -1, 1);
  v.log_scales = ref::uniform<double>(g.log_scales.size(), rng, -1, 1);
  v.quats = ref::uniform<double>(g.quats.size(), rng, -1, 1);
  v.opacity_logits = ref::uniform<double>(g.opacity_logits.size(), rng, -1, 1);
  v.sh = ref::uniform<double>(g.sh.size(), rng, -1, 1);
  const double time = 0.37;
  const ref::DeformGrads<double> r = ref::deform_backward(f, g, time, v);
  auto loss = [&] { return weighted(ref::deform_forward(f, g, time), v); };
  // The loss is piecewise polynomial of low degree in every input, so central differences are
  // limited by round-off (eps |L| / h with h = 1e-6) rather than truncation. Measured worst, relative
  // to the largest gradient: means 2.7e-10, planes 4.6e-9, MLP 9.5e-10.
  CHECK(fd_worst(g.means, r.v.means, loss) < 1e-8);
  CHECK(fd_worst(f.planes, r.v_planes, loss) < 1e-8);
  CHECK(fd_worst(f.mlp, r.v_mlp, loss) < 1e-8);
  // The other raw parameters pass through: deformed = canonical + delta.
  CHECK(r.v.log_scales == v.log_scales);
  CHECK(r.v.quats == v.quats);
  CHECK(r.v.opacity_logits == v.opacity_logits);
  CHECK(r.v.sh == v.sh);
}

TEST_CASE("still Gaussians are not deformed and give the field no gradient") {
  const deform::FieldConfig c = small_config();
  const ref::DeformField<double> f = random_field(c, 5);
  ref::DeformGaussians<double> g = random_gaussians(c, 4, 6);
  g.still_mask.assign(4, 1);
  const ref::DeformGaussians<double> out = ref::deform_forward(f, g, 0.5);
  CHECK(out.means == g.means);
  CHECK(out.sh == g.sh);
  const ref::DeformGrads<double> r = ref::deform_backward(f, g, 0.5, g);  // any cotangent
  CHECK(r.v.means == g.means);
  CHECK(std::all_of(r.v_planes.begin(), r.v_planes.end(), [](double x) { return x == 0; }));
  CHECK(std::all_of(r.v_mlp.begin(), r.v_mlp.end(), [](double x) { return x == 0; }));
}

TEST_CASE("hexplane regularisers match their definition and central finite differences in double") {
  const deform::FieldConfig c = small_config();
  ref::DeformField<double> f = random_field(c, 7);
  const ref::RegWeights w{.plane_tv = 0.3, .time_smoothness = 0.7, .l1_time = 0.2};
  std::vector<double> grad(f.planes.size(), 0.0);
  ref::hexplane_regularisers(f.shape, f.planes, w, &grad);
  auto loss = [&] { return ref::hexplane_regularisers<double>(f.shape, f.planes, w, nullptr); };
  // Quadratic terms plus |1 - P| away from its kink (planes are U(0.5, 1.5), none within 1e-6 of 1):
  // round-off only, measured 3.6e-9 relative.
  CHECK(fd_worst(f.planes, grad, loss) < 1e-8);

  // Constant planes of value 1: every term vanishes. A time plane linear along t: smooth = 0 too.
  std::fill(f.planes.begin(), f.planes.end(), 1.0);
  CHECK(loss() == 0.0);
  const uint32_t xt = gpu::deform_plane_offset(f.shape, 0, 2), rx = c.resolution[0];
  for (uint32_t t = 0; t < c.resolution[3]; ++t)
    for (uint32_t k = 0; k < rx * c.channels; ++k) f.planes[xt + t * rx * c.channels + k] = 1.0 + 0.5 * t;
  // Only the L1 term of that plane: mean of 0.5 t over t = 0..4 is 1, weighted by l1_time.
  CHECK(loss() == doctest::Approx(0.2 * 1.0).epsilon(1e-12));
  // A quadratic along y in the xy plane: second difference 2 a everywhere.
  std::fill(f.planes.begin(), f.planes.end(), 1.0);
  for (uint32_t y = 0; y < c.resolution[1]; ++y)
    for (uint32_t k = 0; k < rx * c.channels; ++k) f.planes[y * rx * c.channels + k] = 0.25 * y * y;
  CHECK(loss() == doctest::Approx(0.3 * 0.25).epsilon(1e-12));  // (2 * 0.25)^2 = 0.25, times plane_tv
}

TEST_CASE("initial field: spatial planes in [0.1, 0.5), time planes 1, xavier weights, PyTorch biases, seeded") {
  const gpu::DeformShape s = deform::deform_shape(small_config());
  const std::vector<float> planes = deform::initial_planes(s, 11), mlp = deform::initial_mlp(s, 11);
  for (uint32_t l = 0; l < s.levels; ++l)
    for (uint32_t p = 0; p < 6; ++p) {
      const bool time_plane = S4D_DEFORM_PLANE_AXIS_V(p) == S4D_DEFORM_TIME_AXIS;
      const uint32_t b = gpu::deform_plane_offset(s, l, p), e = b + gpu::deform_plane_floats(s, l, p);
      for (uint32_t k = b; k < e; ++k) REQUIRE((time_plane ? planes[k] == 1.0f : planes[k] >= 0.1f && planes[k] < 0.5f));
    }
  auto check_linear = [&](uint32_t offset, uint32_t in, uint32_t out) {
    const float xavier = std::sqrt(6.0f / float(in + out)), bias = 1 / std::sqrt(float(in));
    for (uint32_t k = 0; k < out * in; ++k) REQUIRE(std::abs(mlp[offset + k]) <= xavier);
    for (uint32_t k = 0; k < out; ++k) REQUIRE(std::abs(mlp[offset + out * in + k]) <= bias);
  };
  check_linear(0, 6, 6);
  check_linear(gpu::deform_head_offset(s, 4) + 42, 6, 48);
  CHECK(deform::initial_mlp(s, 11) == mlp);
  CHECK(deform::initial_mlp(s, 12) != mlp);
  CHECK(deform::initial_planes(s, 12) != planes);
}

namespace {

// The twin's features of a point under `c` with float planes (the trainer's).
std::vector<double> features_of(const deform::FieldConfig& c, const std::vector<float>& planes, const double* xyz, double t) {
  ref::DeformField<double> f;
  f.shape = deform::deform_shape(c);
  for (int k = 0; k < 3; ++k) f.aabb_max[k] = c.aabb_max[k], f.aabb_scale[k] = 2.0 / (double(c.aabb_min[k]) - c.aabb_max[k]);
  f.planes.assign(planes.begin(), planes.end());
  return ref::hexplane_features(f, xyz, double(deform::grid_time(c, t)));
}

// Largest relative difference of the two fields' features over random points of `b`'s box and
// times in `b`'s time range.
double worst_feature_gap(const deform::FieldConfig& a, const std::vector<float>& pa, const deform::FieldConfig& b,
                         const std::vector<float>& pb, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (int n = 0; n < 200; ++n) {
    double x[3];
    for (int k = 0; k < 3; ++k) x[k] = b.aabb_min[k] + u(rng) * (double(b.aabb_max[k]) - b.aabb_min[k]);
    const double t = b.time_range[0] + u(rng) * (double(b.time_range[1]) - b.time_range[0]);
    const std::vector<double> fa = features_of(a, pa, x, t), fb = features_of(b, pb, x, t);
    for (size_t k = 0; k < fa.size(); ++k) worst = std::max(worst, std::abs(fa[k] - fb[k]) / std::max(1e-3, std::abs(fa[k])));
  }
  return worst;
}

}  // namespace

TEST_CASE("resampled planes: the same field inside the new box, where its texels nest or the planes are affine") {
  const deform::FieldConfig a = small_config();
  const gpu::DeformShape sa = deform::deform_shape(a);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.5f, 1.5f);
  std::vector<float> planes(gpu::deform_planes_total(sa));
  for (float& v : planes) v = u(rng);

  // The same box and resolution: the same floats.
  CHECK(deform::resample_planes(a, a, planes) == planes);

  // The half of the box at the AABB's minimum, with the same texel counts, halves every cell on
  // every level (texel 0 sits at the maximum, and half the box is a whole number of half cells);
  // twice the time texels less one halve the time cells. Measured worst: 1.5e-7 (the new texels
  // rounded to float).
  deform::FieldConfig half = a;
  for (int k = 0; k < 3; ++k) half.aabb_max[k] = 0.5f * (a.aabb_min[k] + a.aabb_max[k]);
  half.resolution[3] = 2 * a.resolution[3] - 1;
  CHECK(worst_feature_gap(a, planes, half, deform::resample_planes(a, half, planes), 1) < 1e-6);

  // The time axis onto the times [0, 1] alone: 3 texels there are the old 5's last three (over
  // [-1, 1]), so the field is the same at every time in [0, 1]. Measured worst: 0.
  deform::FieldConfig later = a;
  later.time_range = {0, 1};
  later.resolution[3] = 3;
  CHECK(worst_feature_gap(a, planes, later, deform::resample_planes(a, later, planes), 3) < 1e-6);

  // Planes affine in their two coordinates are kept by bilinear resampling onto any box and
  // resolution: every point of the new box gets the old features. Measured worst: 1.9e-7.
  for (uint32_t l = 0; l < sa.levels; ++l)
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      const uint32_t ru = gpu::deform_axis_res(sa, l, S4D_DEFORM_PLANE_AXIS_U(p));
      const uint32_t rv = gpu::deform_axis_res(sa, l, S4D_DEFORM_PLANE_AXIS_V(p));
      float* plane = planes.data() + gpu::deform_plane_offset(sa, l, p);
      for (uint32_t j = 0; j < rv; ++j)
        for (uint32_t i = 0; i < ru; ++i)
          for (uint32_t c = 0; c < sa.channels; ++c)
            plane[(j * ru + i) * sa.channels + c] = static_cast<float>(1.0 + 0.3 * i / (ru - 1) - 0.2 * j / (rv - 1) + 0.1 * c);
    }
  deform::FieldConfig odd = a;
  odd.resolution = {7, 3, 9, 4};
  odd.aabb_min = {-0.7f, -0.2f, 0.3f};
  odd.aabb_max = {0.4f, 1.1f, 1.9f};
  CHECK(worst_feature_gap(a, planes, odd, deform::resample_planes(a, odd, planes), 2) < 1e-6);

  // What cannot be carried over is refused by name.
  deform::FieldConfig other = a;
  other.channels = 4;
  CHECK_THROWS_WITH_AS(deform::resample_planes(a, other, planes), doctest::Contains("channels is 4"), std::invalid_argument);
  other = a, other.multires = {1};
  CHECK_THROWS_WITH_AS(deform::resample_planes(a, other, planes), doctest::Contains("multires has 1 levels"), std::invalid_argument);
  planes.pop_back();
  CHECK_THROWS_WITH_AS(deform::resample_planes(a, a, planes), doctest::Contains("planes hold"), std::invalid_argument);
}
