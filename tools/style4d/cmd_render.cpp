// style4d render: option parsing, the mode switch (--run or --ply), and the --ply mode, which renders
// a standard 3DGS PLY from NeRF-style cameras into DIR/<name>.png (RGB over the background) and
// DIR/<name>.exr (R, G, B, A, Z), plus DIR/render.json. Every input is read and checked before
// anything is written. The --run mode is in render_run.cpp.
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "args.h"
#include "commands.h"
#include "device_json.h"
#include "render_modes.h"
#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/util/atomic_file.h"
#include "s4d/util/progress.h"
#include "style_args.h"

namespace s4d::cli {
namespace {

// Expected depth: the alpha-weighted depth sum divided by the accumulated alpha; 0 where nothing
// was blended.
std::vector<float> expected_depth(const std::vector<float>& depth_sum, const std::vector<float>& alpha) {
  std::vector<float> z(depth_sum.size(), 0.0f);
  for (size_t k = 0; k < z.size(); ++k)
    if (alpha[k] > 1e-6f) z[k] = depth_sum[k] / alpha[k];
  return z;
}

}  // namespace

std::array<float, 3> parse_background(const std::string& text) {
  std::array<float, 3> bg{};
  std::istringstream in(text);
  char comma = 0;
  if (!(in >> bg[0] >> comma >> bg[1] >> comma >> bg[2]) || !in.eof())
    throw UsageError("--background: expected R,G,B (for example 0,0,0 or 1,1,1), got '" + text + "'");
  return bg;
}

nlohmann::json storage_json(splat::Storage storage, size_t sh_style_bytes, const engine::Context& ctx) {
  return {{"precision", storage == splat::Storage::f16 ? "f16" : "f32"},
          {"sh_style_bytes", sh_style_bytes},
          {"device_memory_peak_bytes", ctx.memory_peak()}};
}

int cmd_render(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      group("a trained run (--run)"),
      {"run", "a training run directory (style4d train): render one of its protocols", true, "RUN"},
      {"path", "test (each test camera over the test times), spiral (around the scene over t in [0,1]),\n"
               "                        train:CAM (training camera CAM, e.g. train:cam01, over its times) or a camera\n"
               "                        path FILE.json with a time per frame (the viewer records them)", true, "PATH"},
      {"style", "render this trained style instead of the original scene", true, "NAME"},
      mix_spec(),
      alpha_spec(),
      {"format", "png (default), exr (R, G, B, A, Z) or mp4 (one video per sequence)", true, "FORMAT"},
      {"spiral-frames", "--path spiral: number of frames (default 120)", true, "N", {"frames"}},
      {"flow", "also write the renderer's exact optical flow, flow/fw_NNNN.exr and bw_NNNN.exr", false, ""},
      group("a 3DGS PLY (--ply)"),
      {"ply", "standard 3DGS PLY (binary little endian)", true, "FILE"},
      {"cameras", "NeRF-style transforms.json (OpenGL camera-to-world)", true, "FILE"},
      {"sh-degree", "render with at most this SH degree (default: all the PLY stores)", true, "D"},
      {"size", "image size for cameras without w/h (default: required in the JSON)", true, "WxH"},
      group("both"),
      {"out", "output directory (created)", true, "DIR"},
      {"background", "background colour R,G,B in [0,1] (default: --run the run's, --ply 0,0,0)", true, "R,G,B"},
      half_spec(),
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage(
        "render", "--run RUN --path test|spiral|train:CAM|FILE.json --out DIR [--style NAME [--mix NAME2 --alpha A]]\n"
                  "       [--format png|exr|mp4] [--spiral-frames N] [--flow] [--half]\n"
                  "       style4d render --ply FILE --cameras transforms.json --out DIR [--half]",
        "--run: renders a trained run along a protocol. test: one sequence per test camera, fixed, at\n"
        "every test-view time, in DIR/<camera>/; spiral: around the scene (a spiral in front of a\n"
        "forward-facing rig, a helix around a surrounding one, both looking at the point nearest to all\n"
        "training cameras' axes) while time runs over [0, 1]; train:CAM: training camera CAM over its\n"
        "times; FILE.json: a camera path, each frame with its camera and time (a path recorded in\n"
        "`style4d view` replays through the 4D run and any style or blend; docs/protocols.md). Frames are NNNN.png, NNNN.exr or video.mp4; --flow adds flow/fw_NNNN.exr (frame k to\n"
        "k+1) and flow/bw_NNNN.exr (k+1 to k), channels u and v in pixels, exact from the Gaussians'\n"
        "motion. DIR/frames.json lists every frame's time and camera; DIR/render.json the summary.\n"
        "--mix NAME2 --alpha A renders the blend (1 - A) NAME + A NAME2 of two styles of the run (either\n"
        "may be original): colour and opacity changes and the style MLPs' weights interpolated.\n\n"
        "--ply: renders a standard 3D Gaussian Splatting PLY from NeRF-style cameras: per frame\n"
        "DIR/<name>.png (RGB over the background) and DIR/<name>.exr (R, G, B, A = accumulated\n"
        "alpha, Z = expected depth, the alpha-normalised camera-space z), where <name> is the last\n"
        "component of the frame's file_path. Writes DIR/render.json with per-frame statistics.\n\n"
        "--half (both modes) holds the SH and style MLP weights on the device as half-precision floats:\n"
        "half their memory, at the accuracy docs/rasterizer.md measures; render.json records the storage\n"
        "and its bytes.",
        specs);
    return 0;
  }
  if (args.get("run") && args.get("ply")) throw UsageError("--run and --ply are two modes; give one");
  if (args.get("run")) return render_run(args);
  for (const char* o : {"path", "style", "mix", "alpha", "format", "spiral-frames", "flow"})
    if (args.get(o) || args.flag(o)) throw UsageError(std::string("--") + o + " needs --run RUN");
  return render_ply(args);
}

int render_ply(const Args& args) {
  const std::filesystem::path ply_path = args.require("ply"), cameras_path = args.require("cameras");
  const std::filesystem::path out = args.require("out");
  const std::array<float, 3> background = parse_background(args.get_or("background", "0,0,0"));
  const int sh_degree = parse_number<int>("sh-degree", args.get_or("sh-degree", "-1"));
  if (sh_degree < -1 || sh_degree > 3) throw UsageError("--sh-degree: expected 0, 1, 2 or 3");

  const std::optional<std::pair<int, int>> default_size =
      args.get("size") ? std::optional(parse_size("size", *args.get("size"))) : std::nullopt;

  // Read and check everything before writing anything.
  const io::GaussianCloud cloud = io::read_ply_gaussians(ply_path);
  const std::vector<io::CameraView> views = io::read_nerf_cameras(cameras_path, default_size);
  std::cerr << "[render] " << cloud.size() << " Gaussians (SH degree " << cloud.sh_degree << ") from " << ply_path
            << ", " << views.size() << " cameras from " << cameras_path << "\n";

  engine::Context ctx;
  const splat::Storage storage = parse_storage(args);
  splat::DeviceGaussians gaussians(ctx, cloud, "ply", storage);
  splat::Rasterizer rasterizer(ctx);
  std::filesystem::create_directories(out);

  util::Progress progress("render", views.size());
  nlohmann::json frames = nlohmann::json::array();
  for (size_t f = 0; f < views.size(); ++f) {
    const io::CameraView& view = views[f];
    const auto t0 = std::chrono::steady_clock::now();
    const splat::RenderStats stats =
        rasterizer.forward(gaussians.params(sh_degree), splat::to_splat_camera(view), background);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const size_t npix = static_cast<size_t>(view.width) * static_cast<size_t>(view.height);
    io::ImageF rgb{view.width, view.height, 3, ctx.download<float>(rasterizer.rgb(), 3 * npix)};
    const std::vector<float> alpha = ctx.download<float>(rasterizer.alpha(), npix);
    const std::vector<float> depth = expected_depth(ctx.download<float>(rasterizer.depth(), npix), alpha);
    std::vector<float> r(npix), g(npix), b(npix);
    for (size_t k = 0; k < npix; ++k) r[k] = rgb.data[3 * k], g[k] = rgb.data[3 * k + 1], b[k] = rgb.data[3 * k + 2];
    io::write_png(out / (view.name + ".png"), rgb);
    io::write_exr(out / (view.name + ".exr"), view.width, view.height,
                  {{"R", r.data()}, {"G", g.data()}, {"B", b.data()}, {"A", alpha.data()}, {"Z", depth.data()}});
    frames.push_back({{"name", view.name},
                      {"width", view.width},
                      {"height", view.height},
                      {"instances", stats.instances},
                      {"longest_tile_list", stats.longest_tile_list},
                      {"ms", ms}});
    progress.update(f + 1, {{"ms", ms}});
  }
  progress.finish({});
  const nlohmann::json summary = {{"ply", ply_path.string()},
                                  {"cameras", cameras_path.string()},
                                  {"num_gaussians", cloud.size()},
                                  {"sh_degree", sh_degree < 0 ? cloud.sh_degree : std::min(sh_degree, cloud.sh_degree)},
                                  {"background", background},
                                  {"storage", storage_json(storage, gaussians.sh_bytes(), ctx)},
                                  {"device", device_json(ctx.info())},
                                  {"frames", frames}};
  util::write_file_atomic(out / "render.json", summary.dump(2) + "\n");
  std::cout << "rendered " << views.size() << " frames into " << out.string() << "\n";
  return 0;
}

}  // namespace s4d::cli
