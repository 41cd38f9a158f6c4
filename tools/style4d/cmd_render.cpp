// style4d render --ply FILE --cameras transforms.json --out DIR: renders a standard 3DGS PLY from
// NeRF-style cameras into DIR/<name>.png (RGB over the background) and DIR/<name>.exr (R, G, B, A,
// Z), plus DIR/render.json. Every input is read and checked before anything is written.
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
#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/util/atomic_file.h"
#include "s4d/util/progress.h"

namespace s4d::cli {
namespace {

std::array<float, 3> parse_background(const std::string& text) {
  std::array<float, 3> bg{};
  std::istringstream in(text);
  char comma = 0;
  if (!(in >> bg[0] >> comma >> bg[1] >> comma >> bg[2]) || !in.eof())
    throw std::invalid_argument("--background: expected R,G,B (for example 0,0,0 or 1,1,1), got '" + text + "'");
  return bg;
}

// Expected depth: the alpha-weighted depth sum divided by the accumulated alpha; 0 where nothing
// was blended.
std::vector<float> expected_depth(const std::vector<float>& depth_sum, const std::vector<float>& alpha) {
  std::vector<float> z(depth_sum.size(), 0.0f);
  for (size_t k = 0; k < z.size(); ++k)
    if (alpha[k] > 1e-6f) z[k] = depth_sum[k] / alpha[k];
  return z;
}

}  // namespace

int cmd_render(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"ply", "standard 3DGS PLY (binary little endian)", true, "FILE"},
      {"cameras", "NeRF-style transforms.json (OpenGL camera-to-world)", true, "FILE"},
      {"out", "output directory (created)", true, "DIR"},
      {"background", "background colour R,G,B in [0,1] (default 0,0,0)", true, "R,G,B"},
      {"sh-degree", "render with at most this SH degree (default: all the PLY stores)", true, "D"},
      {"size", "image size for cameras without w/h (default: required in the JSON)", true, "WxH"},
      {"run", "a training run directory (renders its protocols; needs `style4d train`)", true, "RUN"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("render", "--ply FILE --cameras transforms.json --out DIR",
                       "Renders a standard 3D Gaussian Splatting PLY from NeRF-style cameras: per frame\n"
                       "DIR/<name>.png (RGB over the background) and DIR/<name>.exr (R, G, B, A = accumulated\n"
                       "alpha, Z = expected depth, the alpha-normalised camera-space z), where <name> is the last\n"
                       "component of the frame's file_path. Writes DIR/render.json with per-frame statistics.",
                       specs);
    return 0;
  }
  if (args.get("run"))
    throw std::invalid_argument(
        "--run needs a trained run directory, and training (`style4d train`) is not part of this build yet; "
        "render a PLY with --ply FILE --cameras transforms.json");
  const std::filesystem::path ply_path = args.require("ply"), cameras_path = args.require("cameras");
  const std::filesystem::path out = args.require("out");
  const std::array<float, 3> background = parse_background(args.get_or("background", "0,0,0"));
  const int sh_degree = parse_number<int>("sh-degree", args.get_or("sh-degree", "-1"));
  if (sh_degree < -1 || sh_degree > 3) throw std::invalid_argument("--sh-degree: expected 0, 1, 2 or 3");

  const std::optional<std::pair<int, int>> default_size =
      args.get("size") ? std::optional(parse_size("size", *args.get("size"))) : std::nullopt;

  // Read and check everything before writing anything.
  const io::GaussianCloud cloud = io::read_ply_gaussians(ply_path);
  const std::vector<io::CameraView> views = io::read_nerf_cameras(cameras_path, default_size);
  std::cerr << "[render] " << cloud.size() << " Gaussians (SH degree " << cloud.sh_degree << ") from " << ply_path
            << ", " << views.size() << " cameras from " << cameras_path << "\n";

  engine::Context ctx;
  splat::DeviceGaussians gaussians(ctx, cloud, "ply");
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
                                  {"device", device_json(ctx.info())},
                                  {"frames", frames}};
  util::write_file_atomic(out / "render.json", summary.dump(2) + "\n");
  std::cout << "rendered " << views.size() << " frames into " << out.string() << "\n";
  return 0;
}

}  // namespace s4d::cli
