// `s4d_bench_splat --style`: the style variant of the rasterizer family (GaussianParams::style)
// against the plain one on the same scene (splat_scene.h) and device: wall-clock forward() and
// backward() of each, measured alternately so load changes on a shared machine hit both alike, with
// tile instances, pixel-Gaussian pairs and the time of each stage (run::stage_ms_json). One JSON
// line per (scene, variant) on stdout, with the 1-minute load average around the point; a table on
// stderr. The smallest scene's style image is checked against the CPU twin. Timings are never
// pass/fail.
//
//   s4d_bench_splat --style [--sizes 128x128:1000,... | --ply F --cameras transforms.json [--camera K]
//                           | --suite peer] [--repeats 5] [--depth ndc|relative] [--cas]
//
// The scenes are s4d_bench_splat's: --sizes seeded random ones, --ply a 3DGS PLY seen by camera K
// (default 0) of a transforms.json, --suite peer the PyTorch peer's kind of scene (peer_scene.h) at
// 1,000 Gaussians @ 128x128, 10,000 @ 256x256 and 100,000 @ 512x512.
// The MLPs are SuperGaussians' initialisation: weights uniform in (-0.5, 0.5), biases zero.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/engine/buffer_from.h"
#include "s4d/engine/context.h"
#include "s4d/ref/style_raster_ref.h"
#include "s4d/splat/rasterizer.h"
#include "peer_scene.h"
#include "scene_options.h"
#include "s4d/engine/stage_timer.h"
#include "s4d/run/stage_times.h"
#include "splat_bench.h"
#include "splat_scene.h"
#include "style_splat_bench.h"

namespace {

using nlohmann::json;
using namespace s4d;

constexpr std::array<float, 3> kBackground = {0.25f, 0.5f, 0.75f};

struct Options : bench::SceneOptions {
  Options() { points = {{128, 128, 1000}, {256, 256, 10000}}; }
  int repeats = 5;
  ref::StyleDepth depth = ref::StyleDepth::ndc;
  bool cas = false;
};

std::optional<Options> parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--style") continue;  // how the caller chose this bench
    const std::string a = argv[i], value = i + 1 < argc ? argv[i + 1] : "";
    if (bench::parse_scene_option(argc, argv, i, o)) {
      continue;
    } else if (a == "--repeats" && !value.empty()) {
      o.repeats = std::stoi(argv[++i]);
    } else if (a == "--depth" && (value == "ndc" || value == "relative")) {
      o.depth = value == "ndc" ? ref::StyleDepth::ndc : ref::StyleDepth::relative;
      ++i;
    } else if (a == "--cas") {
      o.cas = true;
    } else if (a == "--help") {
      return std::nullopt;
    } else {
      throw std::invalid_argument("unknown or incomplete option '" + a + "'");
    }
  }
  bench::check_scene_options(o);
  if (o.repeats < 1) throw std::invalid_argument("need at least one repeat");
  if (o.peer_suite) o.points = bench::kPeerSuite;
  if (!o.ply.empty()) o.points = {{}};  // one scene, from the files
  return o;
}

double load_average() {
  std::ifstream f("/proc/loadavg");
  double load = -1;
  f >> load;
  return load;
}

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// A scene's parameters, gradient buffers and a random RGB cotangent on the device, with and without
// style MLPs.
struct Device {
  bench::DeviceScene scene;
  engine::Buffer weights;
  splat::PerAttr<engine::Buffer> v_attrs;  // gradients of the cloud's attributes and style_mlp
  engine::Buffer v_rgb;
  splat::StyleMlp style;
  splat::GaussianParams plain, styled;
  splat::GaussianGrads grads;

  Device(engine::Context& ctx, const ref::Gaussians<float>& g, const ref::StyleMlp<float>& mlp, size_t pixels)
      : scene(ctx, g),
        weights(engine::buffer_from(ctx, "style weights", mlp.weights)) {
    for (splat::Attr a : {splat::Attr::means, splat::Attr::log_scales, splat::Attr::quats, splat::Attr::opacity_logits,
                          splat::Attr::sh, splat::Attr::style_mlp}) {
      v_attrs[a] = engine::Buffer(ctx, std::string("v_") + splat::attr_name(a),
                            g.size() * splat::attr_floats(a, static_cast<uint32_t>(g.sh_coeffs())) * 4);
      grads[a] = &v_attrs[a];
    }
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<float> v(3 * pixels);
    for (float& x : v) x = u(rng);
    v_rgb = engine::buffer_from(ctx, "v_rgb", v);
    style = {.time = mlp.time,
             .depth = static_cast<splat::StyleDepth>(mlp.depth),
             .depth_scale = mlp.depth_scale,
             .input_sigmoid = mlp.input_sigmoid};
    plain = scene.params;
    styled = plain;
    styled.style = &style;
    styled[splat::Attr::style_mlp] = &weights;
  }
};

struct Measured {
  std::vector<double> fwd, bwd;
  splat::RenderStats stats;
  engine::StageTotals stages;
};

void run_once(splat::Rasterizer& r, const splat::GaussianParams& p, Device& d, const splat::Camera& cam,
              Measured& m, bool record) {
  engine::StageTimer timer(r.context(), run::kStepStages);  // one per run: the variants alternate
  std::optional<engine::StageTimer::Window> window(std::in_place, record ? &timer : nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  m.stats = r.forward(p, cam, kBackground);
  const double fwd = ms_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  r.backward(p, {.v_rgb = &d.v_rgb}, d.grads);
  const double bwd = ms_since(t1);
  window.reset();
  if (record) m.fwd.push_back(fwd), m.bwd.push_back(bwd), m.stages += timer.totals();
}

// The scene of one point: a random one, the peer's, or the files'.
bench::SplatScene make_scene(const bench::SplatPoint& pt, const Options& o) {
  if (!o.ply.empty()) return bench::load_splat_scene(o.ply, o.cameras, o.camera);
  if (o.peer_suite) {
    const bench::PeerScene peer = bench::make_peer_scene(pt.gaussians, pt.width, pt.height);
    return bench::to_splat_scene(peer.cloud, peer.cameras[0]);
  }
  return bench::make_splat_scene(pt.width, pt.height, pt.gaussians, 1);
}

// Measures one scene; false when the twin check fails.
bool run_point(engine::Context& ctx, const json& device, const bench::SplatScene& scene, const Options& o, bool twin) {
  const bench::SplatPoint pt{.width = static_cast<uint32_t>(scene.camera.width),
                             .height = static_cast<uint32_t>(scene.camera.height),
                             .gaussians = static_cast<uint32_t>(scene.gaussians.size())};
  ref::StyleMlp<float> mlp;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  for (uint32_t i = 0; i < pt.gaussians; ++i)
    for (size_t k = 0; k < ref::kStyleMlpStride; ++k) {
      const bool bias = (k >= S4D_STYLE_MLP_B1 && k < S4D_STYLE_MLP_W2) ||
                        (k >= S4D_STYLE_MLP_B2 && k < S4D_STYLE_MLP_W3) || k >= S4D_STYLE_MLP_B3;
      mlp.weights.push_back(bias ? 0.0f : u(rng));
    }
  mlp.time = 0.25f, mlp.depth = o.depth, mlp.depth_scale = 1.0f;
  const size_t pixels = size_t{pt.width} * pt.height;
  Device d(ctx, scene.gaussians, mlp, pixels);
  const splat::Camera cam = bench::to_gpu_camera(scene.camera);
  const splat::RasterizerOptions options{
      .force_cas_atomics = o.cas, .backward_pixels = o.bwd_pixels, .forward_pixels = o.fwd_pixels};
  splat::Rasterizer plain(ctx, "bench plain", options);
  splat::Rasterizer styled(ctx, "bench style", options);

  const double load_before = load_average();
  Measured mp, ms;
  for (int r = -1; r < o.repeats; ++r) {  // run -1 grows buffers and compiles pipelines
    run_once(plain, d.plain, d, cam, mp, r >= 0);
    run_once(styled, d.styled, d, cam, ms, r >= 0);
  }
  const double load_after = load_average();
  const bench::Timing pf = bench::summarise_ms(mp.fwd), pb = bench::summarise_ms(mp.bwd);
  const bench::Timing sf = bench::summarise_ms(ms.fwd), sb = bench::summarise_ms(ms.bwd);

  bool ok = true;
  json base = device;
  base["scene"] = !o.ply.empty() ? "file" : o.peer_suite ? "peer" : "random";
  if (!o.ply.empty()) base.update({{"ply", o.ply}, {"cameras", o.cameras}, {"camera", o.camera}});
  base.update({{"bench", "style_splat"},
               {"sh_degree", scene.gaussians.sh_degree},
               {"width", pt.width},
               {"height", pt.height},
               {"n_gaussians", pt.gaussians},
               {"depth_mode", o.depth == ref::StyleDepth::ndc ? "ndc" : "relative"},
               {"atomics", o.cas ? "cas" : "float"},
               {"bwd_pixels", styled.backward_pixels()},
               {"fwd_pixels", styled.forward_pixels()},
               {"instances", ms.stats.instances},
               {"longest_tile_list", ms.stats.longest_tile_list},
               {"timing", "wall clock around forward() and backward(), which submit and wait"},
               {"repeats", o.repeats},
               {"loadavg_1m_before", load_before},
               {"loadavg_1m_after", load_after}});
  const size_t pixels_n = size_t{pt.width} * pt.height;
  for (const bool style : {false, true}) {
    const bench::Timing& f = style ? sf : pf;
    const bench::Timing& b = style ? sb : pb;
    const bench::PixelPairs pairs = bench::count_pixel_pairs(ctx, style ? styled : plain, pixels_n);
    json line = base;
    line.update({{"variant", style ? "style" : "plain"},
                 {"pixel_pairs_listed", uint64_t{(style ? ms : mp).stats.instances} * S4D_TILE_PIXELS},
                 {"pixel_pairs_evaluated", pairs.evaluated},
                 {"pixel_pairs_blended", pairs.blended},
                 {"stage_ms", run::stage_ms_json((style ? ms : mp).stages, static_cast<uint64_t>(o.repeats))},
                 {"ms_fwd_p50", f.ms_p50}, {"ms_fwd_min", f.ms_min}, {"ms_fwd_max", f.ms_max},
                 {"ms_bwd_p50", b.ms_p50}, {"ms_bwd_min", b.ms_min}, {"ms_bwd_max", b.ms_max},
                 {"fwd_ratio_to_plain", f.ms_p50 / pf.ms_p50}, {"bwd_ratio_to_plain", b.ms_p50 / pb.ms_p50}});
    if (style && twin) {
      const auto t = ref::render_style_fwd(scene.gaussians, mlp, scene.camera, kBackground);
      const std::vector<float> rgb = ctx.download<float>(styled.rgb(), 3 * pixels);
      double worst = 0;
      for (size_t k = 0; k < rgb.size(); ++k)
        worst = std::max(worst, std::abs(static_cast<double>(rgb[k]) - t.img.rgb[k]));
      ok = worst <= bench::kTwinTolerance;  // not finite compares false
      line.update({{"matches_twin", ok}, {"twin_max_abs_diff", worst}});
    }
    std::cout << line.dump() << std::endl;
  }
  std::fprintf(stderr, "%5ux%-5u %7u %9u %9.1f %9.1f %6.2f %9.1f %9.1f %6.2f %5.2f-%.2f\n", pt.width, pt.height,
               pt.gaussians, ms.stats.instances, pf.ms_p50, sf.ms_p50, sf.ms_p50 / pf.ms_p50, pb.ms_p50, sb.ms_p50,
               sb.ms_p50 / pb.ms_p50, load_before, load_after);
  return ok;
}

}  // namespace

namespace s4d::bench {

int style_bench_main(int argc, char** argv) {
  const char* usage =
      "usage: s4d_bench_splat --style [--sizes WxH:N,... | --ply F --cameras transforms.json [--camera K]\n"
      "                               | --suite peer] [--repeats R] [--depth ndc|relative] [--cas]\n";
  std::optional<Options> parsed;
  try {
    parsed = parse(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "s4d_bench_splat --style: " << e.what() << "\n" << usage;
    return 2;
  }
  if (!parsed) {
    std::cout << usage;
    return 0;
  }
  const Options& o = *parsed;
  bool all_ok = true;
  try {
    engine::Context ctx;
    const auto& info = ctx.info();
    const json device = {{"device", info.name}, {"driver", info.driver_name + " " + info.driver_info}};
    std::fprintf(stderr, "device: %s (%s)\n%-11s %7s %9s %9s %9s %6s %9s %9s %6s %s\n", info.name.c_str(),
                 info.driver_info.c_str(), "size", "N", "instances", "plain fwd", "style fwd", "ratio", "plain bwd",
                 "style bwd", "ratio", "load");
    auto pixels = [](const bench::SplatPoint& p) { return uint64_t{p.width} * p.height; };
    size_t twin_at = 0;  // the twin check runs at the fewest pixels
    for (size_t i = 1; i < o.points.size(); ++i)
      if (pixels(o.points[i]) < pixels(o.points[twin_at])) twin_at = i;
    for (size_t i = 0; i < o.points.size(); ++i)
      all_ok = run_point(ctx, device, make_scene(o.points[i], o), o, i == twin_at) && all_ok;
  } catch (const std::exception& e) {
    std::cerr << "s4d_bench_splat --style: error: " << e.what() << "\n";
    return 1;
  }
  return all_ok ? 0 : 1;
}

}  // namespace s4d::bench
