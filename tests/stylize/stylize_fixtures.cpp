#include "stylize_fixtures.h"

#include <cmath>

#include "s4d/synth/camera_rig.h"
#include "s4d/synth/render.h"
#include "s4d/synth/scene.h"

namespace s4d::test {

std::vector<io::ImageF> synth_frames(int count, double first_t, double dt) {
  const synth::Scene scene;
  const auto cameras = synth::arc_cameras(synth::ArcRig{}, scene.centre, 3, 160, 120);
  std::vector<io::ImageF> frames;
  for (int k = 0; k < count; ++k) {
    synth::RenderedView view = synth::render_view(scene, cameras[1], first_t + k * dt, {});
    frames.push_back({view.width, view.height, 3, std::move(view.rgb)});
  }
  return frames;
}

std::vector<double> colour_stats(const io::ImageF& image) {
  std::vector<double> s(6, 0.0);
  const size_t n = static_cast<size_t>(image.width) * image.height;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) s[c] += image.data[3 * i + c];
  for (int c = 0; c < 3; ++c) s[c] /= static_cast<double>(n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) s[3 + c] += (image.data[3 * i + c] - s[c]) * (image.data[3 * i + c] - s[c]);
  for (int c = 0; c < 3; ++c) s[3 + c] = std::sqrt(s[3 + c] / static_cast<double>(n));
  return s;
}

namespace {

std::vector<double> gradient_magnitude(const io::ImageF& im) {
  auto lum = [&](int x, int y) {
    const float* p = &im.data[(static_cast<size_t>(y) * im.width + x) * 3];
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  };
  std::vector<double> g;
  for (int y = 1; y + 1 < im.height; ++y)
    for (int x = 1; x + 1 < im.width; ++x) g.push_back(std::hypot(lum(x + 1, y) - lum(x - 1, y), lum(x, y + 1) - lum(x, y - 1)));
  return g;
}

}  // namespace

double gradient_correlation(const io::ImageF& a, const io::ImageF& b) {
  const std::vector<double> ga = gradient_magnitude(a), gb = gradient_magnitude(b);
  double ma = 0, mb = 0;
  for (size_t i = 0; i < ga.size(); ++i) ma += ga[i], mb += gb[i];
  ma /= static_cast<double>(ga.size()), mb /= static_cast<double>(gb.size());
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < ga.size(); ++i) {
    sab += (ga[i] - ma) * (gb[i] - mb);
    saa += (ga[i] - ma) * (ga[i] - ma);
    sbb += (gb[i] - mb) * (gb[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

}  // namespace s4d::test
