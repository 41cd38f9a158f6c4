// Deformation field kernels' speed on the chosen device (S4D_DEVICE to pick another): the forward
// (row "deform_fwd": deform_feat + deform_fwd's layer sets), the backward (row "deform_bwd", or
// "deform_bwd_cas" with --cas: the recomputed activations, deform_cot, deform_bwd's layer sets,
// deform_feat_bwd + deform_wgrad) and deform_reg for a preset's field on N random Gaussians
// inside the field's AABB, the last --static fraction of them still (skipped by the field, as the
// trainer's --static-motion puts them last). One JSON line per kernel on stdout, a human table on stderr.
// Timings come from GPU timestamps around each kernel's recorded work, median of --repeats after a
// warm-up run. The backward's gradients (v_means, v_planes, v_mlp) are checked against the double CPU
// twin on the first --check Gaussians (0: none, all moving); the relative errors and "matches_twin"
// (all below tests/gpu/test_deform.cpp's 1e-5) go into the bwd line.
//
//   s4d_bench_deform [--preset fast] [--gaussians 15000] [--static 0] [--repeats 5] [--cas] [--check 2000]
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/deform/deformation_field.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/engine/check.h"
#include "s4d/engine/context.h"
#include "s4d/engine/timestamps.h"
#include "s4d/ref/deform_ref.h"
#include "s4d/ref/random_deform.h"
#include "s4d/run/train_config.h"
#include "timing.h"

namespace {

using nlohmann::json;
using namespace s4d;

struct Options {
  std::string preset = "fast";
  uint32_t gaussians = 15000;
  double still_fraction = 0;
  int repeats = 5;
  bool cas = false;
  uint32_t check = 2000;
};

using ref::uniform;

std::vector<double> to_double(const std::vector<float>& v) { return {v.begin(), v.end()}; }

// Largest |gpu - ref| relative to the largest |ref|; infinity for a non-finite GPU value.
double max_rel(const std::vector<float>& gpu, const std::vector<double>& ref) {
  double worst = 0, scale = 1e-30;
  for (size_t k = 0; k < gpu.size() && k < ref.size(); ++k) {
    if (!std::isfinite(gpu[k])) return INFINITY;
    worst = std::max(worst, std::abs(gpu[k] - ref[k]));
    scale = std::max(scale, std::abs(ref[k]));
  }
  return worst / scale;
}

// Canonical Gaussians (host copy and device buffers) with random cotangents of the deformed ones.
struct Scene {
  ref::DeformGaussians<float> host, v_host;
  engine::Buffer means, log_scales, quats, opacity, sh;
  engine::Buffer v_means, v_log_scales, v_quats, v_opacity, v_sh;
  engine::Buffer out_means, out_log_scales, out_quats, out_opacity, out_sh;
  uint32_t n = 0, still_count = 0, sh_coeffs = 1;

  deform::CanonicalGaussians canonical() const {
    return {{{&means, &log_scales, &quats, &opacity, &sh}}, n, still_count, sh_coeffs};
  }
  splat::GaussianBuffers<engine::Buffer> deformed() {
    return {{&out_means, &out_log_scales, &out_quats, &out_opacity, &out_sh}};
  }
  splat::GaussianGrads grads() { return {{&v_means, &v_log_scales, &v_quats, &v_opacity, &v_sh}}; }
};

Scene make_scene(engine::Context& ctx, const deform::FieldConfig& c, uint32_t n, unsigned seed) {
  std::mt19937 rng(seed);
  Scene s;
  s.n = n;
  s.sh_coeffs = (c.heads & S4D_DEFORM_HEAD_SH) != 0 ? S4D_DEFORM_SH_COEFFS : 1;  // the sh head deforms degree 3
  s.host = ref::random_gaussians<float>(c.aabb_min, c.aabb_max, n, rng,
                                        {.margin = 0, .log_scale_lo = -4, .log_scale_hi = -2, .sh_coeffs = s.sh_coeffs});
  s.v_host.means = uniform(3 * size_t{n}, rng, -1, 1);
  s.v_host.log_scales = uniform(3 * size_t{n}, rng, -1, 1);
  s.v_host.quats = uniform(4 * size_t{n}, rng, -1, 1);
  s.v_host.opacity_logits = uniform(n, rng, -1, 1);
  s.v_host.sh = uniform(3 * size_t{n} * s.sh_coeffs, rng, -1, 1);
  s.means = engine::buffer_from(ctx, "means", s.host.means);
  s.log_scales = engine::buffer_from(ctx, "log_scales", s.host.log_scales);
  s.quats = engine::buffer_from(ctx, "quats", s.host.quats);
  s.opacity = engine::buffer_from(ctx, "opacity_logits", s.host.opacity_logits);
  s.sh = engine::buffer_from(ctx, "sh", s.host.sh);
  s.v_means = engine::buffer_from(ctx, "v_means", s.v_host.means);
  s.v_log_scales = engine::buffer_from(ctx, "v_log_scales", s.v_host.log_scales);
  s.v_quats = engine::buffer_from(ctx, "v_quats", s.v_host.quats);
  s.v_opacity = engine::buffer_from(ctx, "v_opacity_logits", s.v_host.opacity_logits);
  s.v_sh = engine::buffer_from(ctx, "v_sh", s.v_host.sh);
  s.out_means = engine::Buffer(ctx, "out means", size_t{n} * 12);
  s.out_log_scales = engine::Buffer(ctx, "out log_scales", size_t{n} * 12);
  s.out_quats = engine::Buffer(ctx, "out quats", size_t{n} * 16);
  s.out_opacity = engine::Buffer(ctx, "out opacity", size_t{n} * 4);
  s.out_sh = engine::Buffer(ctx, "out sh", size_t{n} * 12 * s.sh_coeffs);
  return s;
}

// Median GPU time of `record` over the repeats, after one warm-up run; `before` runs untimed first
// in the same submission (e.g. restoring in-place inputs).
template <class Before, class Record>
bench::Timing time_kernel(engine::Context& ctx, int repeats, const char* name, Before before, Record record) {
  engine::TimestampQueries q(ctx, 2, std::string(name) + " timestamps");
  std::vector<double> ms;
  for (int r = -1; r < repeats; ++r) {  // run -1 warms up (pipeline compilation) and is not counted
    engine::Recorder rec(ctx, name);
    rec.reset_queries(q);
    before(rec);
    rec.barrier();
    rec.timestamp(q, 0);
    record(rec);
    rec.timestamp(q, 1);
    ctx.run(std::move(rec));
    if (r >= 0) ms.push_back(q.elapsed_ms(0, 1));
  }
  return bench::summarise_ms(std::move(ms));
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--preset") o.preset = value();
    else if (a == "--gaussians") o.gaussians = static_cast<uint32_t>(std::stoul(value()));
    else if (a == "--static") o.still_fraction = std::stod(value());
    else if (a == "--repeats") o.repeats = std::stoi(value());
    else if (a == "--check") o.check = static_cast<uint32_t>(std::stoul(value()));
    else if (a == "--cas") o.cas = true;
    else throw std::invalid_argument("unknown argument '" + a + "'");
  }
  if (o.gaussians == 0 || o.repeats < 1) throw std::invalid_argument("--gaussians and --repeats must be at least 1");
  if (!(o.still_fraction >= 0 && o.still_fraction <= 1)) throw std::invalid_argument("--static must be in [0, 1]");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    engine::Context ctx;
    const run::TrainConfig tc = run::preset_config(o.preset);
    const deform::FieldConfig fc = run::field_config(tc, {-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f});
    deform::DeformationField field(ctx, fc, 7, "bench field", {.force_cas_atomics = o.cas});
    std::mt19937 rng(8);
    // Planes around 1, as trained ones start, so the 6-fold products stay O(1).
    field.upload_planes(uniform(field.plane_floats(), rng, 0.6f, 1.4f));
    Scene s = make_scene(ctx, fc, o.gaussians, 9);
    s.still_count = static_cast<uint32_t>(std::lround(o.still_fraction * o.gaussians));
    const float time = 0.37f;
    const deform::RegulariserWeights w{.plane_tv = 2e-4f, .time_smoothness = 1e-3f, .l1_time_planes = 1e-4f};

    const bench::Timing fwd = time_kernel(ctx, o.repeats, "deform_fwd", [](engine::Recorder&) {},
                                          [&](engine::Recorder& rec) { field.record_forward(rec, s.canonical(), time, s.deformed()); });
    // v_means is updated in place: restore it, and zero the gradients, before every timed run.
    engine::Buffer v_means_start = engine::buffer_from(ctx, "v_means start", s.v_host.means);
    auto restore = [&](engine::Recorder& rec) {
      rec.copy(v_means_start, s.v_means, size_t{o.gaussians} * 12);
      field.record_zero_grads(rec);
    };
    const bench::Timing bwd = time_kernel(ctx, o.repeats, o.cas ? "deform_bwd_cas" : "deform_bwd", restore,
                                          [&](engine::Recorder& rec) { field.record_backward(rec, s.canonical(), time, s.grads()); });
    const bench::Timing reg = time_kernel(ctx, o.repeats, "deform_reg", [](engine::Recorder&) {},
                                          [&](engine::Recorder& rec) { field.record_regularisers(rec, w); });

    // Twin check of the backward on the first `check` Gaussians (the CPU twin is slow at full size).
    json check = nullptr;
    if (o.check > 0) {
      const uint32_t m = std::min(o.check, o.gaussians);
      Scene c = make_scene(ctx, fc, m, 9);
      engine::Recorder rec(ctx, "bench deform check");
      field.record_zero_grads(rec);
      rec.barrier();
      field.record_backward(rec, c.canonical(), time, c.grads());
      ctx.run(std::move(rec));
      ref::DeformField<double> twin{field.shape(), {}, {}, to_double(field.download_planes()), to_double(field.download_mlp())};
      const std::array<float, 3> scale = deform::aabb_scale(fc);
      for (int k = 0; k < 3; ++k) twin.aabb_max[k] = fc.aabb_max[k], twin.aabb_scale[k] = scale[k];
      auto dbl = [](const ref::DeformGaussians<float>& g) {
        return ref::DeformGaussians<double>{to_double(g.means), to_double(g.log_scales), to_double(g.quats),
                                            to_double(g.opacity_logits), to_double(g.sh), {}};
      };
      // The twin gets the grid's time, as the kernels do (the preset's time range).
      const ref::DeformGrads<double> r =
          ref::deform_backward(twin, dbl(c.host), double(deform::grid_time(fc, time)), dbl(c.v_host));
      check = {{"gaussians", m},
               {"v_means_max_rel", max_rel(ctx.download<float>(c.v_means, 3 * size_t{m}), r.v.means)},
               {"v_planes_max_rel", max_rel(ctx.download<float>(field.v_planes(), field.plane_floats()), r.v_planes)},
               {"v_mlp_max_rel", max_rel(ctx.download<float>(field.v_mlp(), field.mlp_floats()), r.v_mlp)}};
      // tests/gpu/test_deform.cpp's tolerance
      check["matches_twin"] = check["v_means_max_rel"].get<double>() < 1e-5 &&
                              check["v_planes_max_rel"].get<double>() < 1e-5 && check["v_mlp_max_rel"].get<double>() < 1e-5;
    }

    const auto& info = ctx.info();
    const json base = {{"device", info.name},
                       {"driver", info.driver_name + " " + info.driver_info},
                       {"preset", o.preset},
                       {"gaussians", o.gaussians},
                       {"static_gaussians", s.still_count},  // the JSON key predates "still"
                       {"mlp_floats", field.mlp_floats()},
                       {"plane_floats", field.plane_floats()},
                       {"timing", "gpu timestamps around the kernel's recorded work"},
                       {"repeats", o.repeats}};
    std::fprintf(stderr, "device: %s (%s), preset %s, %u Gaussians (%u still), MLP %u floats, planes %u floats\n"
                 "%-16s %9s %9s %9s\n",
                 info.name.c_str(), info.driver_info.c_str(), o.preset.c_str(), o.gaussians, s.still_count, field.mlp_floats(),
                 field.plane_floats(), "kernel", "ms p50", "ms min", "ms max");
    const std::pair<const char*, const bench::Timing*> rows[] = {
        {"deform_fwd", &fwd}, {o.cas ? "deform_bwd_cas" : "deform_bwd", &bwd}, {"deform_reg", &reg}};
    for (const auto& [name, t] : rows) {
      json line = base;
      line.update({{"bench", name}, {"ms_gpu_p50", t->ms_p50}, {"ms_gpu_min", t->ms_min}, {"ms_gpu_max", t->ms_max}});
      if (t == &bwd) line["twin_check"] = check;
      std::cout << line.dump() << std::endl;
      std::fprintf(stderr, "%-16s %9.2f %9.2f %9.2f\n", name, t->ms_p50, t->ms_min, t->ms_max);
    }
    if (!check.is_null())
      std::fprintf(stderr, "twin check (%u Gaussians), max rel: v_means %.2g, v_planes %.2g, v_mlp %.2g\n",
                   check["gaussians"].get<uint32_t>(), check["v_means_max_rel"].get<double>(),
                   check["v_planes_max_rel"].get<double>(), check["v_mlp_max_rel"].get<double>());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "s4d_bench_deform: %s\n", e.what());
    return 1;
  }
}
