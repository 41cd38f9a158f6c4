// The background a dataset's frames were shot or rendered on, found from the frames themselves:
// frames with alpha are composited on the layout's convention; opaque frames whose borders are one
// uniform colour (a synthetic object on black or white, alpha dropped as in many public copies of
// D-NeRF) were rendered on that colour, and training must draw on it too, or the Gaussians spend
// themselves painting the background. Real captures have no uniform border and keep the default.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dataset_parts.h"
#include "video_decoders.h"

namespace s4d::data::detail {
namespace {

constexpr size_t kProbeFrames = 4;       // training frames decoded, spread over the views
constexpr int kBand = 2;                 // border band width in pixels
constexpr float kUniformTolerance = 0.08f;  // per channel, around the band's median (8-bit noise and AA edges)
constexpr double kUniformShare = 0.9;    // share of band pixels within the tolerance for "uniform"
constexpr float kConflictDistance = 0.25f;  // an explicit background this far from the borders is reported

struct BorderColour {
  bool uniform = false;
  std::array<float, 3> median{};
};

BorderColour border_colour(const io::ImageF& image) {
  const int w = image.width, h = image.height, c = image.channels;
  std::array<std::vector<float>, 3> band;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x >= kBand && x < w - kBand && y >= kBand && y < h - kBand) continue;
      const float* p = &image.data[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * static_cast<size_t>(c)];
      for (size_t k = 0; k < 3; ++k) band[k].push_back(p[c < 3 ? 0 : k]);
    }
  }
  BorderColour out;
  if (band[0].empty()) return out;
  for (size_t k = 0; k < 3; ++k) {
    std::vector<float> sorted = band[k];
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    out.median[k] = sorted[sorted.size() / 2];
  }
  size_t close = 0;
  for (size_t i = 0; i < band[0].size(); ++i) {
    bool near = true;
    for (size_t k = 0; k < 3; ++k) near = near && std::abs(band[k][i] - out.median[k]) <= kUniformTolerance;
    close += near ? 1 : 0;
  }
  out.uniform = static_cast<double>(close) >= kUniformShare * static_cast<double>(band[0].size());
  return out;
}

std::string colour_text(const std::array<float, 3>& c) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f,%.2f,%.2f", static_cast<double>(c[0]), static_cast<double>(c[1]),
                static_cast<double>(c[2]));
  return buf;
}

}  // namespace

BackgroundProbe probe_background(const Dataset& dataset) {
  std::vector<const View*> train;
  for (const View& v : dataset.views) {
    if (!v.test) train.push_back(&v);
  }
  BackgroundProbe probe;
  if (train.empty()) return probe;
  VideoDecoders videos;
  std::array<float, 3> sum{};
  bool all_uniform = true;
  std::vector<std::array<float, 3>> medians;
  const size_t count = std::min(kProbeFrames, train.size());
  for (size_t i = 0; i < count; ++i) {
    const View& view = *train[i * (train.size() - 1) / std::max<size_t>(1, count - 1)];
    const io::ImageF image = view.frame_in_file >= 0 ? videos.read(view.image, view.frame_in_file) : io::read_png(view.image);
    ++probe.frames;
    if (image.channels == 2 || image.channels == 4) probe.alpha = true;
    const BorderColour border = border_colour(image);
    all_uniform = all_uniform && border.uniform;
    medians.push_back(border.median);
    for (size_t k = 0; k < 3; ++k) sum[k] += border.median[k] / static_cast<float>(count);
  }
  // One colour for the whole capture: every probed frame's border agrees with the mean.
  for (const auto& m : medians) {
    for (size_t k = 0; k < 3; ++k) all_uniform = all_uniform && std::abs(m[k] - sum[k]) <= kUniformTolerance;
  }
  if (!probe.alpha && all_uniform) probe.border = sum;
  return probe;
}

void choose_background(Dataset& dataset, const LoadOptions& options, const std::array<float, 3>& layout_default) {
  const BackgroundProbe probe = options.probe_background ? probe_background(dataset) : BackgroundProbe{};
  if (options.background) {
    dataset.background = *options.background;
    dataset.background_source = "option";
    if (probe.border) {
      float distance = 0;
      for (size_t k = 0; k < 3; ++k) distance = std::max(distance, std::abs((*probe.border)[k] - dataset.background[k]));
      if (distance > kConflictDistance) {
        dataset.background_conflict = "the frames are opaque with a uniform " + colour_text(*probe.border) +
                                      " border, but the background asked for is " + colour_text(dataset.background);
      }
    }
  } else if (probe.alpha) {
    dataset.background = layout_default;
    dataset.background_source = "alpha";  // composited on the layout's convention
  } else if (probe.border) {
    dataset.background = *probe.border;
    dataset.background_source = "borders";
  } else {
    dataset.background = layout_default;
    dataset.background_source = options.probe_background ? "layout (opaque frames)" : "layout";
  }
  for (size_t k = 0; k < 3; ++k) {
    const float b = dataset.background[k];
    if (!(b >= 0.0f && b <= 1.0f)) fail(dataset.root, "background components must be in [0, 1]");
  }
}

}  // namespace s4d::data::detail
