// The viewer's frame time vs image size and Gaussian count on the chosen device (S4D_DEVICE to pick
// another): FrameRenderer::render (rasterize, then pack to 8-bit pixels) plus the wait for the
// device, which is what each windowed frame costs before the copy, the panel and presentation.
// One JSON line per size on stdout, a table on stderr. Timings are never pass/fail.
//
//   s4d_bench_viewer [--sizes 320x240:10000,...] [--repeats 5]
//   s4d_bench_viewer --run RUN [--orbit 60] [--size 640x480] [--frame-budget-ms 100] [--repeats 3]
//
// Scenes are bench/splat_scene's seeded random Gaussians (SH degree 3, a few to tens of pixels
// wide at any resolution), seen from its camera.
//
// With --run, the moving camera: a trained run's original scene at t = 0 along an orbit of N frames
// (one turn about the viewer's pivot, starting at dataset camera 0), as the window renders it
// while the camera moves: at AdaptiveResolution's scale under the frame budget ("adaptive"), and at
// full resolution ("full"). Each repeat runs both orbits back to back, each after one still
// full-resolution frame (which the policy measures, as in the window). One JSON line per orbit
// with its fps, mean scale, process CPU ms, submissions and host waits per frame, then the median fps of each mode and their ratio.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <ctime>
#include <memory>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/scene/download_cloud.h"
#include "s4d/scene/static_scene.h"
#include "s4d/scene/trained_run.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/viewer/adaptive_resolution.h"
#include "s4d/viewer/camera_control.h"
#include "s4d/viewer/dataset_cameras.h"
#include "s4d/viewer/frame_renderer.h"
#include "scene_options.h"
#include "splat_scene.h"
#include "timing.h"

namespace {

using nlohmann::json;

using Point = s4d::bench::SplatPoint;
using s4d::bench::parse_point;

struct Options {
  std::vector<Point> points = {{320, 240, 10000}, {640, 480, 10000}, {640, 480, 100000}, {1280, 720, 100000}};
  int repeats = 5;
  // The moving camera (--run).
  std::string run;
  int orbit_frames = 60;
  uint32_t width = 640, height = 480;
  double budget_ms = 100;
};

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
    } else if (a == "--run" && i + 1 < argc) {
      o.run = argv[++i];
    } else if (a == "--orbit" && i + 1 < argc) {
      o.orbit_frames = std::stoi(argv[++i]);
    } else if (a == "--size" && i + 1 < argc) {
      const Point p = parse_point(std::string(argv[++i]) + ":0");
      o.width = p.width, o.height = p.height;
    } else if (a == "--frame-budget-ms" && i + 1 < argc) {
      o.budget_ms = std::stod(argv[++i]);
    } else {
      throw std::invalid_argument("unknown or incomplete option '" + a +
                                  "' (usage: s4d_bench_viewer [--sizes WxH:N,...] [--repeats R] | --run RUN "
                                  "[--orbit N] [--size WxH] [--frame-budget-ms MS] [--repeats R])");
    }
  }
  if (o.points.empty() || o.repeats < 1) throw std::invalid_argument("need at least one size and one repeat");
  if (o.orbit_frames < 1 || o.width == 0 || o.height == 0 || !(o.budget_ms > 0))
    throw std::invalid_argument("--orbit, --size and --frame-budget-ms must be positive");
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
    renderer.render_now(source, cam, 0.0, s4d::viewer::PixelOrder::bgra);
    const double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (r >= 0) ms.push_back(t);
  }
  return s4d::bench::summarise_ms(ms);
}

struct Orbit {
  double fps = 0, mean_scale = 0, ms_p50 = 0;
  double cpu_ms_per_frame = 0;                         // process CPU time (all threads, lavapipe's included)
  double submissions_per_frame = 0, waits_per_frame = 0;  // engine::Context counters
};

double process_cpu_ms() { return 1000.0 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// One orbit of the moving camera at `budget_ms` (0: full resolution), after a still full-resolution
// frame that the policy measures.
Orbit orbit(s4d::engine::Context& ctx, s4d::scene::SceneSource& source, s4d::viewer::FrameRenderer& renderer,
            s4d::viewer::CameraControl control, const Options& o, double budget_ms) {
  s4d::viewer::AdaptiveResolution resolution({.budget_ms = budget_ms});
  std::vector<double> ms;
  double total_ms = 0, total_scale = 0, cpu_ms = 0;
  uint64_t submissions = 0, waits = 0;
  for (int f = -1; f < o.orbit_frames; ++f) {
    const bool moving = f >= 0;
    if (moving) control.orbit(2 * std::acos(-1.0) / o.orbit_frames, 0);
    const double scale = resolution.scale(moving);
    const uint64_t s0 = ctx.submissions(), w0 = ctx.host_waits();
    const double c0 = process_cpu_ms();
    const auto t0 = std::chrono::steady_clock::now();
    renderer.render_now(source, control.camera(o.width, o.height), 0.0, s4d::viewer::PixelOrder::bgra, scale);
    const double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    resolution.measured(t, scale);
    if (!moving) continue;
    ms.push_back(t);
    total_ms += t, total_scale += scale, cpu_ms += process_cpu_ms() - c0;
    submissions += ctx.submissions() - s0, waits += ctx.host_waits() - w0;
  }
  const double frames = o.orbit_frames;
  return {.fps = 1000.0 * frames / total_ms,
          .mean_scale = total_scale / frames,
          .ms_p50 = s4d::bench::summarise_ms(ms).ms_p50,
          .cpu_ms_per_frame = cpu_ms / frames,
          .submissions_per_frame = static_cast<double>(submissions) / frames,
          .waits_per_frame = static_cast<double>(waits) / frames};
}

int bench_orbit(s4d::engine::Context& ctx, const Options& o) {
  const s4d::scene::TrainedRun run = s4d::scene::read_trained_run(o.run);
  const std::unique_ptr<s4d::scene::SceneSource> source = s4d::scene::open_scene(ctx, run);
  s4d::viewer::FrameRenderer renderer(ctx, run.dataset.background);
  const std::vector<s4d::io::CameraView> cameras = s4d::viewer::dataset_cameras(run.dataset);
  const s4d::splat::Camera first = s4d::splat::to_splat_camera(cameras[0]);
  const double depth =
      s4d::viewer::median_depth(cameras[0], s4d::scene::download_cloud(ctx, source->at(0.0, first)).means, 1.0);
  s4d::viewer::CameraControl control(s4d::viewer::estimate_up(cameras), 1.0);
  control.snap(cameras[0], depth);
  const auto& info = ctx.info();
  std::fprintf(stderr, "device: %s (%s)\n%s: %u Gaussians, %d-frame orbit at %ux%u, budget %.0f ms\n%-9s %7s %9s %6s %8s %6s %6s\n",
               info.name.c_str(), info.driver_info.c_str(), o.run.c_str(), source->size(), o.orbit_frames, o.width,
               o.height, o.budget_ms, "mode", "fps", "ms p50", "scale", "cpu ms", "subm", "waits");
  std::vector<double> fps_full, fps_adaptive;
  for (int r = 0; r < o.repeats; ++r) {
    for (const bool adaptive : {false, true}) {
      const Orbit result = orbit(ctx, *source, renderer, control, o, adaptive ? o.budget_ms : 0);
      (adaptive ? fps_adaptive : fps_full).push_back(result.fps);
      const json line = {{"bench", "viewer_orbit"},
                         {"device", info.name},
                         {"driver", info.driver_name + " " + info.driver_info},
                         {"run", o.run},
                         {"n_gaussians", source->size()},
                         {"width", o.width},
                         {"height", o.height},
                         {"frames", o.orbit_frames},
                         {"mode", adaptive ? "adaptive" : "full"},
                         {"budget_ms", adaptive ? o.budget_ms : 0},
                         {"fps", result.fps},
                         {"ms_p50", result.ms_p50},
                         {"mean_scale", result.mean_scale},
                         {"cpu_ms_per_frame", result.cpu_ms_per_frame},
                         {"submissions_per_frame", result.submissions_per_frame},
                         {"host_waits_per_frame", result.waits_per_frame}};
      std::cout << line.dump() << std::endl;
      std::fprintf(stderr, "%-9s %7.2f %9.1f %6.3f %8.1f %6.2f %6.2f\n", adaptive ? "adaptive" : "full", result.fps,
                   result.ms_p50, result.mean_scale, result.cpu_ms_per_frame, result.submissions_per_frame,
                   result.waits_per_frame);
    }
  }
  std::sort(fps_full.begin(), fps_full.end());
  std::sort(fps_adaptive.begin(), fps_adaptive.end());
  const double full = fps_full[fps_full.size() / 2], adaptive = fps_adaptive[fps_adaptive.size() / 2];
  std::cout << json{{"bench", "viewer_orbit_ratio"}, {"fps_full", full}, {"fps_adaptive", adaptive},
                    {"ratio", adaptive / full}}.dump()
            << std::endl;
  std::fprintf(stderr, "median fps: full %.2f, adaptive %.2f, ratio %.2fx\n", full, adaptive, adaptive / full);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    s4d::engine::Context ctx;
    if (!o.run.empty()) return bench_orbit(ctx, o);
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
