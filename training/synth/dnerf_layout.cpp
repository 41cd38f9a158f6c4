#include "s4d/synth/dnerf_layout.h"

#include <cmath>
#include <cstdio>
#include <numeric>
#include <nlohmann/json.hpp>

#include "s4d/io/image_io.h"
#include "s4d/util/atomic_file.h"

namespace s4d::synth {

namespace fs = std::filesystem;

namespace {

std::string view_name(int k) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "r_%03d", k);
  return buf;
}

// Camera-to-world in OpenGL axes: columns right, up, back (the camera looks along -back), centre.
nlohmann::json transform_matrix(const PinholeCamera& c) {
  return {{c.right.x, c.up.x, c.back.x, c.position.x},
          {c.right.y, c.up.y, c.back.y, c.position.y},
          {c.right.z, c.up.z, c.back.z, c.position.z},
          {0.0, 0.0, 0.0, 1.0}};
}

}  // namespace

int monocular_camera(int frame, int cams) {
  const int others = cams - 1;
  // A stride coprime with the count visits every camera before repeating.
  int stride = std::max(1, others / 2 + 1);
  while (std::gcd(stride, others) != 1) ++stride;
  return 1 + (frame * stride) % others;
}

void write_dnerf_views(const fs::path& dir, const Scene& scene, const std::vector<PinholeCamera>& cameras,
                       const SynthOptions& options, const RenderSettings& settings, const ProgressFn& progress) {
  const uint64_t total = 2 * static_cast<uint64_t>(options.frames);
  uint64_t done = 0;
  const double angle_x = 2 * std::atan(0.5 * cameras[0].width / cameras[0].focal);
  for (const std::string split : {"train", "test"}) {
    fs::create_directories(dir / split);
    nlohmann::json frames = nlohmann::json::array();
    for (int f = 0; f < options.frames; ++f) {
      const double t = static_cast<double>(f) / (options.frames - 1);
      const PinholeCamera& cam = cameras[static_cast<size_t>(split == "train" ? monocular_camera(f, options.cams) : 0)];
      RenderedView view = render_view(scene, cam, t, settings);
      io::write_png(dir / split / (view_name(f) + ".png"), io::ImageF{view.width, view.height, 3, std::move(view.rgb)});
      frames.push_back({{"file_path", "./" + split + "/" + view_name(f)}, {"time", t}, {"transform_matrix", transform_matrix(cam)}});
      if (progress) progress(++done, total);
    }
    util::write_file_atomic(dir / ("transforms_" + split + ".json"),
                            nlohmann::json{{"camera_angle_x", angle_x}, {"frames", frames}}.dump(2) + "\n");
  }
}

}  // namespace s4d::synth
