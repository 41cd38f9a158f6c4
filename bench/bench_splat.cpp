// GPU rasterizer speed vs image size and Gaussian count on the chosen device (S4D_DEVICE to pick
// another), next to the device's ceiling for the same blend loop. Per scene, one JSON line for the
// ceiling and one per rasterizer pass on stdout, with tile instances, pixel-Gaussian pairs and the
// time of each stage over the measured runs (project, sort, raster, backward: run::stage_ms_json;
// both passes unless --only fwd); a human table on stderr. Timings are never pass/fail; the
// smallest scene's forward image is checked against the CPU twin.
//
//   s4d_bench_splat [--sizes 128x128:1000,...] [--repeats 5] [--only fwd|fwdbwd]
//   s4d_bench_splat --ply F --cameras transforms.json [--camera K] [...]
//   s4d_bench_splat --suite peer [...]
//   s4d_bench_splat --write-peer-scene DIR [--gaussians N] [--size WxH]
//   s4d_bench_splat --style [scene options] [--repeats 5] [--depth ndc|relative] [--cas]
//
// --sizes draws seeded random scenes (splat_scene.h). --ply/--cameras benchmark a standard 3DGS
// PLY seen by camera K (default 0) of a transforms.json. --suite peer runs the PyTorch peer's kind
// of scene (peer_scene.h, seed 1) at 1,000 Gaussians @ 128x128, 10,000 @ 256x256 and 100,000 @
// 512x512. --write-peer-scene writes that scene as DIR/points.ply + DIR/transforms.json (default
// 1,000 Gaussians at 128x128) for other tools and exits. --only fwd skips the backward (and its
// gradient buffers); --only fwdbwd skips the forward line and the ceiling. A scene the device
// cannot hold (memory, buffer range, lavapipe's tile-list cap) gets a line with "skipped": true and
// the reason. --style measures the style variant against the plain one instead
// (style_splat_bench.h).
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "blend_ceiling.h"
#include "peer_scene.h"
#include "scene_options.h"
#include "s4d/engine/check.h"
#include "s4d/engine/context.h"
#include "s4d/run/stage_times.h"
#include "splat_bench.h"
#include "style_splat_bench.h"

namespace {

using nlohmann::json;
using s4d::bench::SplatPoint;
using s4d::bench::SceneOptions;
using s4d::bench::kPeerSuite;
using s4d::bench::parse_scene_option;
using s4d::bench::check_scene_options;
using s4d::bench::parse_point;

// What to benchmark: a seeded random scene, the peer's scene, or a PLY and a camera file.
struct Job {
  std::string scene;  // "random", "peer", "file"
  SplatPoint point;   // for random and peer scenes
  std::string ply, cameras;
  size_t camera = 0;

  s4d::bench::SplatScene make() const {
    if (scene == "file") return s4d::bench::load_splat_scene(ply, cameras, camera);
    if (scene == "peer") {
      const auto peer = s4d::bench::make_peer_scene(point.gaussians, point.width, point.height);
      return s4d::bench::to_splat_scene(peer.cloud, peer.cameras[0]);
    }
    return s4d::bench::make_splat_scene(point.width, point.height, point.gaussians, 1);
  }
  json describe() const {
    json j = {{"scene", scene}};
    if (scene == "file") j.update({{"ply", ply}, {"cameras", cameras}, {"camera", camera}});
    if (scene == "peer") j.update({{"seed", 1}, {"ring_camera", 0}});
    return j;
  }
};

struct Options : SceneOptions {
  Options() { points = {{128, 128, 1000}, {256, 256, 10000}, {512, 512, 100000}, {1352, 1014, 200000}}; }
  std::string write_peer;  // a directory: write the peer scene there and exit
  SplatPoint peer_point = {128, 128, 1000};
  int repeats = 5;
  bool fwd = true, fwdbwd = true;

  std::vector<Job> jobs() const {
    std::vector<Job> out;
    if (!ply.empty()) out.push_back({.scene = "file", .point = {}, .ply = ply, .cameras = cameras, .camera = camera});
    else
      for (const SplatPoint& p : peer_suite ? kPeerSuite : points)
        out.push_back({.scene = peer_suite ? "peer" : "random", .point = p, .ply = {}, .cameras = {}, .camera = 0});
    return out;
  }
};

// The job the twin check runs at: the fewest pixels, then the fewest Gaussians.
size_t smallest(const std::vector<Job>& jobs) {
  auto key = [](const Job& j) { return std::pair(uint64_t{j.point.width} * j.point.height, j.point.gaussians); };
  size_t best = 0;
  for (size_t i = 1; i < jobs.size(); ++i)
    if (key(jobs[i]) < key(jobs[best])) best = i;
  return best;
}

// A table cell: `v` in printf format `fmt`, or "-" for a value that was not measured (0).
std::string cell(const char* fmt, double v) {
  if (v == 0) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

double mib(size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }
double per_s(uint64_t pairs, double ms) { return ms > 0 ? static_cast<double>(pairs) / (ms * 1e-3) : 0; }

json ceiling_json(json line, const s4d::bench::CeilingTiming& c) {
  line.update({{"bench", "blend_ceiling"},
               {"width", c.width},
               {"height", c.height},
               {"tiles", c.tiles},
               {"list_length", c.list_length},
               {"timing", "gpu timestamps around the dispatch"},
               {"repeats", c.gpu.repeats},
               {"ms_gpu_p50", c.gpu.ms_p50},
               {"ms_gpu_min", c.gpu.ms_min},
               {"ms_gpu_max", c.gpu.ms_max},
               {"pixel_pairs", c.pixel_pairs},
               {"pairs_per_s", c.pairs_per_s},
               {"all_blended", c.all_blended}});
  return line;
}

// What both rasterizer lines of a point share.
json splat_json(json line, const s4d::bench::SplatTiming& t) {
  line.update({{"timing", "wall clock around forward() / forward() + backward(), which submit and wait"},
               {"repeats", t.fwd.repeats},
               {"instances", t.instances},
               {"tiles", t.tiles},
               {"bwd_pixels", t.bwd_pixels},
               {"fwd_pixels", t.fwd_pixels},
               {"avg_tile_list", static_cast<double>(t.instances) / t.tiles},
               {"longest_tile_list", t.longest_tile_list},
               {"pixel_pairs_listed", t.pixel_pairs_listed},
               {"pixel_pairs_blended", t.pixel_pairs_blended},
               {"pixel_pairs_evaluated", t.pixel_pairs_evaluated},
               {"stage_ms", s4d::run::stage_ms_json(t.stages, static_cast<uint64_t>(t.fwd.repeats))},
               {"peak_device_mib", mib(t.device_bytes)}});
  if (t.twin_checked) line.update({{"matches_twin", t.matches_twin}, {"twin_max_abs_diff", t.twin_max_abs_diff}});
  return line;
}

json pass_json(json line, const char* pass, const s4d::bench::Timing& ms, uint64_t pairs) {
  line.update({{"pass", pass},
               {"ms_wall_p50", ms.ms_p50},
               {"ms_wall_min", ms.ms_min},
               {"ms_wall_max", ms.ms_max},
               {"listed_pairs_per_s", per_s(pairs, ms.ms_p50)}});
  return line;
}

// Measures one point and prints its lines; false when a result is wrong. `base` holds the fields
// every line of the point carries (device, size, Gaussian count).
bool run_point(s4d::engine::Context& ctx, const json& base, const s4d::bench::SplatScene& scene, const Options& o,
               bool twin) {
  const auto t = s4d::bench::bench_splat(ctx, scene, o.repeats, o.fwdbwd, twin, 1, {.backward_pixels = o.bwd_pixels, .forward_pixels = o.fwd_pixels});
  const SplatPoint& pt = t.point;
  const json line = splat_json(base, t);
  bool ok = !t.twin_checked || t.matches_twin;
  const double rate = per_s(t.pixel_pairs_listed, t.fwd.ms_p50);
  double ceiling = 0;
  if (o.fwd) {
    const uint32_t list = s4d::bench::ceiling_list_length(t.instances, t.tiles);
    const auto c = s4d::bench::bench_blend_ceiling(ctx, pt.width, pt.height, list, o.repeats);
    std::cout << ceiling_json(base, c).dump() << std::endl;
    ok = ok && c.all_blended;
    ceiling = c.pairs_per_s;
    // Early termination skips listed pairs, so the listed ratio can pass 1; the blended ratio (useful
    // work only) is the lower bound of the loop's efficiency.
    const double blended = per_s(t.pixel_pairs_blended, t.fwd.ms_p50);
    json fl = pass_json(line, "fwd", t.fwd, t.pixel_pairs_listed);
    fl.update({{"blended_pairs_per_s", blended},
               {"ceiling_pairs_per_s", ceiling},
               {"ratio_to_ceiling", ceiling > 0 ? rate / ceiling : 0},
               {"blended_ratio_to_ceiling", ceiling > 0 ? blended / ceiling : 0}});
    std::cout << fl.dump() << std::endl;
  }
  if (o.fwdbwd) std::cout << pass_json(line, "fwdbwd", t.fwdbwd, t.pixel_pairs_listed).dump() << std::endl;
  std::fprintf(stderr, "%5ux%-5u %7u %9.1f %9s %9u %7u %10.3g %10.3g %10s %6s %8.1f %6s\n", pt.width, pt.height,
               pt.gaussians, t.fwd.ms_p50, cell("%.1f", t.fwdbwd.ms_p50).c_str(), t.instances, t.longest_tile_list,
               rate, per_s(t.pixel_pairs_blended, t.fwd.ms_p50), cell("%.3g", ceiling).c_str(),
               cell("%.2f", ceiling > 0 ? rate / ceiling : 0).c_str(), mib(t.device_bytes),
               !t.twin_checked ? "-" : t.matches_twin ? "ok" : "WRONG");
  std::fprintf(stderr, "%13s pairs: %llu listed, %llu evaluated, %llu blended; ms per run (%s):", "",
               static_cast<unsigned long long>(t.pixel_pairs_listed),
               static_cast<unsigned long long>(t.pixel_pairs_evaluated),
               static_cast<unsigned long long>(t.pixel_pairs_blended), t.stages.gpu ? "gpu timestamps" : "host clock");
  for (size_t i = 0; i < t.stages.stages.size(); ++i)
    if (t.stages.ms[i] > 0) std::fprintf(stderr, " %s %.1f", t.stages.stages[i].c_str(), t.stages.ms[i] / o.repeats);
  std::fprintf(stderr, " other %.1f\n", t.stages.other_ms / o.repeats);
  return ok;
}

void print_skipped(json line, const std::string& reason) {
  line.update({{"skipped", true}, {"reason", reason}});
  std::cout << line.dump() << std::endl;
  std::fprintf(stderr, "%s skipped: %s\n", line.value("scene", "").c_str(), reason.c_str());
}

// The options, or nothing for --help. Throws std::invalid_argument on a bad command line.
std::optional<Options> parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const std::string value = i + 1 < argc ? argv[i + 1] : "";
    if (parse_scene_option(argc, argv, i, o)) {
      continue;
    } else if (a == "--write-peer-scene" && !value.empty()) {
      o.write_peer = argv[++i];
    } else if (a == "--gaussians" && !value.empty()) {
      o.peer_point.gaussians = static_cast<uint32_t>(std::stoul(argv[++i]));
    } else if (a == "--size" && !value.empty()) {
      o.peer_point = parse_point(std::string(argv[++i]) + ":" + std::to_string(o.peer_point.gaussians));
    } else if (a == "--repeats" && !value.empty()) {
      o.repeats = std::stoi(argv[++i]);
    } else if (a == "--only" && (value == "fwd" || value == "fwdbwd")) {
      o.fwd = value == "fwd", o.fwdbwd = value == "fwdbwd";
      ++i;
    } else if (a == "--help") {
      return std::nullopt;
    } else {
      throw std::invalid_argument("unknown or incomplete option '" + a + "'");
    }
  }
  check_scene_options(o);
  if (o.repeats < 1) throw std::invalid_argument("need at least one repeat");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--style") return s4d::bench::style_bench_main(argc, argv);
  const char* usage =
      "usage: s4d_bench_splat [--sizes WxH:N,... | --ply F --cameras transforms.json [--camera K] | --suite peer]\n"
      "                       [--repeats R] [--only fwd|fwdbwd] [--bwd-pixels 1|8] [--fwd-pixels 1|8]\n"
      "       s4d_bench_splat --write-peer-scene DIR [--gaussians N] [--size WxH]\n"
      "       s4d_bench_splat --style [scene options] [--repeats R] [--depth ndc|relative] [--cas]\n";
  std::optional<Options> parsed;
  try {
    parsed = parse(argc, argv);
  } catch (const std::exception& e) {  // std::stoul and std::stoi throw on numbers that do not parse
    std::cerr << "s4d_bench_splat: " << e.what() << "\n" << usage;
    return 2;
  }
  if (!parsed) {
    std::cout << usage;
    return 0;
  }
  const Options& o = *parsed;
  bool all_ok = true;
  try {
    if (!o.write_peer.empty()) {
      const SplatPoint& p = o.peer_point;
      s4d::bench::write_peer_scene(o.write_peer, s4d::bench::make_peer_scene(p.gaussians, p.width, p.height));
      std::cout << json{{"wrote", o.write_peer}, {"gaussians", p.gaussians}, {"width", p.width}, {"height", p.height},
                        {"seed", 1}}.dump()
                << std::endl;
      return 0;
    }
    s4d::engine::Context ctx;
    const auto& info = ctx.info();
    const json device = {{"device", info.name}, {"driver", info.driver_name + " " + info.driver_info}};
    std::fprintf(stderr, "device: %s (%s)\n%-11s %7s %9s %9s %9s %7s %10s %10s %10s %6s %8s %6s\n",
                 info.name.c_str(), info.driver_info.c_str(), "size", "N", "fwd ms", "f+b ms", "instances", "longest",
                 "listed/s", "blended/s", "ceiling/s", "ratio", "MiB", "twin");
    const std::vector<Job> jobs = o.jobs();
    const size_t twin_at = smallest(jobs);
    for (size_t i = 0; i < jobs.size(); ++i) {
      json line = device;
      line.update(jobs[i].describe());
      line["bench"] = "splat_raster";
      const s4d::bench::SplatScene scene = jobs[i].make();  // a file that does not read is an error, not a skip
      line.update({{"width", scene.camera.width},
                   {"height", scene.camera.height},
                   {"n_gaussians", scene.gaussians.size()},
                   {"sh_degree", scene.gaussians.sh_degree}});
      try {
        all_ok = run_point(ctx, line, scene, o, i == twin_at) && all_ok;
      } catch (const s4d::engine::VulkanError& e) {
        if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY && e.result() != VK_ERROR_OUT_OF_HOST_MEMORY) throw;
        print_skipped(line, e.what());
      } catch (const std::invalid_argument& e) {  // buffer range, allocation size, instance count
        print_skipped(line, e.what());
      } catch (const std::runtime_error& e) {  // a tile list longer than lavapipe can blend
        print_skipped(line, e.what());
      } catch (const std::bad_alloc&) {
        print_skipped(line, "out of host memory");
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "s4d_bench_splat: error: " << e.what() << "\n";
    return 1;
  }
  return all_ok ? 0 : 1;
}
