#include "s4d/synth/dnerf_layout.h"

#include <algorithm>
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
  return {{c.right[0], c.up[0], c.back[0], c.position[0]},
          {c.right[1], c.up[1], c.back[1], c.position[1]},
          {c.right[2], c.up[2], c.back[2], c.position[2]},
          {0.0, 0.0, 0.0, 1.0}};
}

// RGBA with straight (not premultiplied) colour, as PNG stores it: the render is colour over the sky
// weighted by coverage, so the sky's share comes out again.
io::ImageF straight_rgba(const RenderedView& view, Vec3 sky) {
  io::ImageF out{view.width, view.height, 4, std::vector<float>(view.alpha.size() * 4)};
  const double sky_rgb[3] = {sky[0], sky[1], sky[2]};
  for (size_t i = 0; i < view.alpha.size(); ++i) {
    const float a = view.alpha[i];
    for (size_t c = 0; c < 3; ++c)
      out.data[i * 4 + c] = a > 0 ? static_cast<float>((view.rgb[i * 3 + c] - sky_rgb[c] * (1 - a)) / a) : 0.0f;
    out.data[i * 4 + 3] = a;
  }
  return out;
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
  auto angle_x = [](const PinholeCamera& c) { return 2 * std::atan(0.5 * c.width / c.focal); };
  const bool one_focal = std::all_of(cameras.begin(), cameras.end(), [&](const PinholeCamera& c) { return c.focal == cameras[0].focal; });
  for (const std::string split : {"train", "test"}) {
    fs::create_directories(dir / split);
    nlohmann::json frames = nlohmann::json::array();
    for (int f = 0; f < options.frames; ++f) {
      const double t = static_cast<double>(f) / (options.frames - 1);
      const PinholeCamera& cam = cameras[static_cast<size_t>(split == "train" ? monocular_camera(f, options.cams) : 0)];
      const RenderedView view = render_view(scene, cam, options.still ? 0.0 : t, settings);
      io::write_png(dir / split / (view_name(f) + ".png"), options.rgba ? straight_rgba(view, scene.sky) : io::ImageF{view.width, view.height, 3, view.rgb});
      nlohmann::json frame = {{"file_path", "./" + split + "/" + view_name(f)}, {"time", t}, {"transform_matrix", transform_matrix(cam)}};
      if (!one_focal) frame["camera_angle_x"] = angle_x(cam);  // NeRF transforms allow it per frame
      frames.push_back(std::move(frame));
      if (progress) progress(++done, total);
    }
    util::write_file_atomic(dir / ("transforms_" + split + ".json"),
                            nlohmann::json{{"camera_angle_x", angle_x(cameras[0])}, {"frames", frames}}.dump(2) + "\n");
  }
}

}  // namespace s4d::synth
