// The viewer's frame time vs image size and Gaussian count on the chosen device (S4D_DEVICE to pick
// another): FrameRenderer::render (rasterize, then pack to 8-bit pixels) plus the wait for the
// device, which is what each windowed frame costs before the copy, the panel and presentation.
// One JSON line per size on stdout, a table on stderr. Timings are never pass/fail.
//
//   s4d_bench_viewer [--sizes 320x240:10000,...] [--repeats 5]
//
// Scenes are bench/splat_scene's seeded random Gaussians (SH degree 3, a few to tens of pixels
// wide at any resolution), seen from its camera.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/scene/static_scene.h"
#include "s4d/viewer/frame_renderer.h"
#include "splat_scene.h"
#include "timing.h"

namespace {

using nlohmann::json;

struct Point {
  uint32_t width, height, gaussians;
};

struct Options {
  std::vector<Point> points = {{320, 240, 10000}, {640, 480, 10000}, {640, 480, 100000}, {1280, 720, 100000}};
  int repeats = 5;
};

Point parse_point(const std::string& s) {
  const size_t x = s.find('x'), colon = s.find(':');
  if (x == std::string::npos || colon == std::string::npos || colon < x)
    throw std::invalid_argument("size '" + s + "' is not WxH:N");
  return {static_cast<uint32_t>(std::stoul(s.substr(0, x))),
          static_cast<uint32_t>(std::stoul(s.substr(x + 1, colon - x - 1))),
          static_cast<uint32_t>(std::stoul(s.substr(colon + 1)))};
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sizes" && i + 1 < argc) {
      o.points.clear();
      std::stringstream ss(argv[++i]);
      for (std::string tok; std::getline(ss, tok, ',');) o.points.push_back(parse_point(tok));
    } else if (a == "--repeats" && i + 1 < argc) {
      o.repeats = std::stoi(argv[++i]);
    } else {
      throw std::invalid_argument("unknown or incomplete option '" + a +
                                  "' (usage: s4d_bench_viewer [--sizes WxH:N,...] [--repeats R])");
    }
  }
  if (o.points.empty() || o.repeats < 1) throw std::invalid_argument("need at least one size and one repeat");
  return o;
}

s4d::io::GaussianCloud to_cloud(const s4d::ref::Gaussians<float>& g) {
  return {.means = g.means, .log_scales = g.log_scales, .quats = g.quats, .opacity_logits = g.opacity_logits,
          .sh = g.sh, .sh_degree = 3};
}

// Median frame time over `repeats` frames after one warm-up frame.
s4d::bench::Timing time_frames(s4d::engine::Context& ctx, const Point& pt, int repeats) {
  const s4d::bench::SplatScene scene = s4d::bench::make_splat_scene(pt.width, pt.height, pt.gaussians, 7);
  s4d::scene::StaticScene source(ctx, to_cloud(scene.gaussians));
  s4d::viewer::FrameRenderer renderer(ctx, {0, 0, 0});
  const s4d::splat::Camera cam = s4d::bench::to_gpu_camera(scene.camera);
  std::vector<double> ms;
  for (int r = -1; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    s4d::engine::Recorder rec(ctx, "bench viewer frame");
    renderer.render(source, cam, 0.0, s4d::viewer::PixelOrder::bgra, rec);
    ctx.run(std::move(rec));
    const double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (r >= 0) ms.push_back(t);
  }
  return s4d::bench::summarise_ms(ms);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    s4d::engine::Context ctx;
    const auto& info = ctx.info();
    std::fprintf(stderr, "device: %s (%s)\n%-11s %9s %9s %9s %7s\n", info.name.c_str(), info.driver_info.c_str(),
                 "image", "gaussians", "ms p50", "ms min", "fps");
    for (const Point& pt : o.points) {
      const s4d::bench::Timing t = time_frames(ctx, pt, o.repeats);
      const json line = {{"bench", "viewer_frame"},
                         {"device", info.name},
                         {"driver", info.driver_name + " " + info.driver_info},
                         {"width", pt.width},
                         {"height", pt.height},
                         {"n_gaussians", pt.gaussians},
                         {"repeats", t.repeats},
                         {"ms_p50", t.ms_p50},
                         {"ms_min", t.ms_min},
                         {"ms_max", t.ms_max},
                         {"fps_p50", 1000.0 / t.ms_p50}};
      std::cout << line.dump() << std::endl;
      std::fprintf(stderr, "%5ux%-5u %9u %9.1f %9.1f %7.1f\n", pt.width, pt.height, pt.gaussians, t.ms_p50, t.ms_min,
                   1000.0 / t.ms_p50);
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "s4d_bench_viewer: error: " << e.what() << "\n";
    return 1;
  }
}
