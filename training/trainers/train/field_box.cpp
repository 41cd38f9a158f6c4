#include "s4d/train/field_box.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "s4d_deform.h"

namespace s4d::train {

nlohmann::json FieldBox::json() const {
  return {{"fitted", fitted},         {"old_min", old_min},         {"old_max", old_max},
          {"min", min},               {"max", max},                 {"gaussians", gaussians},
          {"old_resolution", old_resolution}, {"resolution", resolution},
          {"moving", moving},         {"move_limit", move_limit},   {"volume_share", volume_share},
          {"at_step", at_step},       {"why", why}};
}

namespace {

// The q-quantile of v (nearest rank); v is reordered.
float quantile(std::vector<float>& v, double q) {
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

bool path_moves(std::span<const float> lo, std::span<const float> hi, size_t i, double move_limit) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += double(hi[i * 3 + k] - lo[i * 3 + k]) * (hi[i * 3 + k] - lo[i * 3 + k]);
  return std::sqrt(d2) >= move_limit;
}

FieldBox fit_field_box(std::span<const float> lo, std::span<const float> hi, const std::array<float, 3>& old_min,
                       const std::array<float, 3>& old_max, const std::array<uint32_t, 3>& resolution, double move_limit) {
  if (lo.size() != hi.size() || lo.size() % 3 != 0)
    throw std::invalid_argument("fit_field_box: " + std::to_string(lo.size()) + " lowest and " + std::to_string(hi.size()) +
                                " highest coordinates, expected 3 per Gaussian each");
  FieldBox box{.old_min = old_min, .old_max = old_max, .min = old_min, .max = old_max, .old_resolution = resolution,
               .resolution = resolution};
  box.gaussians = static_cast<uint32_t>(lo.size() / 3);
  box.move_limit = move_limit;
  std::array<std::vector<float>, 3> low, high;
  for (size_t i = 0; i < box.gaussians; ++i) {
    if (!path_moves(lo, hi, i, move_limit)) continue;
    for (int k = 0; k < 3; ++k) low[k].push_back(lo[i * 3 + k]), high[k].push_back(hi[i * 3 + k]);
  }
  box.moving = static_cast<uint32_t>(low[0].size());
  if (box.moving < kFieldFitMinMoving) {
    box.why = std::to_string(box.moving) + " of " + std::to_string(box.gaussians) + " Gaussians move (fewer than " +
              std::to_string(kFieldFitMinMoving) + "): too few to tell where the motion is; the box stays";
    return box;
  }
  std::array<float, 3> mn{}, mx{};
  std::array<uint32_t, 3> res{};
  double share = 1;
  for (int k = 0; k < 3; ++k) {
    const double a = quantile(low[k], kFieldFitQuantile), b = quantile(high[k], 1 - kFieldFitQuantile);
    const double pad = kFieldFitPad * std::max(0.0, b - a);
    double m0 = std::max<double>(old_min[k], a - pad), m1 = std::min<double>(old_max[k], b + pad);
    // An axis the motion barely spans keeps 4 old cells, centred on it and inside the old box.
    const double old_size = double(old_max[k]) - old_min[k], cell = old_size / std::max<uint32_t>(1, resolution[k] - 1);
    const double size = std::min(std::max(4 * cell, m1 - m0), old_size);
    const double centre = std::clamp(0.5 * (m0 + m1), old_min[k] + 0.5 * size, old_max[k] - 0.5 * size);
    m0 = centre - 0.5 * size, m1 = centre + 0.5 * size;
    mn[k] = static_cast<float>(m0), mx[k] = static_cast<float>(m1);
    share *= (m1 - m0) / old_size;
    // Cells no larger than before: (texels - 1) x cell covers the new size.
    const auto texels = static_cast<uint32_t>(std::ceil((m1 - m0) / cell - 1e-9)) + 1;
    res[k] = std::clamp<uint32_t>(texels, S4D_DEFORM_MIN_RESOLUTION, resolution[k]);
  }
  box.volume_share = share;
  char text[256];
  if (share > kFieldFitMaxVolumeShare) {
    std::snprintf(text, sizeof text, "the paths of the %u moving Gaussians fill %.0f %% of the box (more than %.0f %%): the box stays",
                  box.moving, 100 * share, 100 * kFieldFitMaxVolumeShare);
    box.why = text;
    return box;
  }
  box.fitted = true;
  box.min = mn, box.max = mx, box.resolution = res;
  std::snprintf(text, sizeof text,
                "the paths of the %u moving Gaussians fill %.0f %% of the box: the planes now span them alone, at %ux%ux%u "
                "texels (were %ux%ux%u) of the same size",
                box.moving, 100 * share, res[0], res[1], res[2], resolution[0], resolution[1], resolution[2]);
  box.why = text;
  return box;
}

nlohmann::json FieldTime::json() const {
  return {{"fitted", fitted},   {"old_resolution", old_resolution}, {"resolution", resolution},
          {"moving", moving},   {"samples", samples},               {"tolerance", tolerance},
          {"error_by_resolution", error_by_resolution}, {"at_step", at_step}, {"why", why}};
}

FieldTime fit_field_time(std::span<const float> paths, uint32_t samples, uint32_t dims, std::span<const uint8_t> moving,
                         uint32_t resolution, const std::array<float, 2>& range, double tolerance) {
  const size_t n = moving.size();
  if (samples < 2 || dims == 0 || paths.size() != size_t{samples} * n * dims)
    throw std::invalid_argument("fit_field_time: " + std::to_string(paths.size()) + " path floats for " + std::to_string(samples) +
                                " samples of " + std::to_string(n) + " Gaussians, expected " + std::to_string(dims) +
                                " per Gaussian per sample");
  FieldTime fit{.old_resolution = resolution, .resolution = resolution, .samples = samples, .tolerance = tolerance};
  std::vector<uint32_t> movers;
  for (uint32_t i = 0; i < n; ++i)
    if (moving[i]) movers.push_back(i);
  fit.moving = static_cast<uint32_t>(movers.size());
  if (fit.moving < kFieldFitMinMoving) {
    fit.why = std::to_string(fit.moving) + " Gaussians move (fewer than " + std::to_string(kFieldFitMinMoving) +
              "): too few to tell how fast; the time axis stays";
    return fit;
  }
  // Value k of Gaussian i at fractional sample position u, linear between the samples.
  auto at = [&](uint32_t i, double u, uint32_t k) {
    const auto s0 = std::min(static_cast<uint32_t>(u), samples - 2);
    const double w = u - s0;
    return (1 - w) * paths[(size_t{s0} * n + i) * dims + k] + w * paths[(size_t{s0 + 1} * n + i) * dims + k];
  };
  // Candidates with at least two samples per texel interval: fewer cannot show what they miss.
  const double span = double(range[1]) - range[0];
  if (!(span > 0)) throw std::invalid_argument("fit_field_time: the time range must be two times, the second larger");
  const uint32_t last = std::min<uint32_t>(resolution - 1, static_cast<uint32_t>((samples - 1) * span / 2) + 1);
  uint32_t chosen = resolution;
  std::vector<float> worst(movers.size());
  for (uint32_t r = S4D_DEFORM_MIN_RESOLUTION; r <= last; ++r) {
    // Sample s (time s / (samples - 1)) lies between texels j and j + 1; the line between them is
    // taken at their times clipped to [0, 1]: a texel at a time no view has is free to continue it.
    std::vector<double> from(samples), to(samples), weight(samples);
    for (uint32_t s = 0; s < samples; ++s) {
      const double t = double(s) / (samples - 1);
      const double j = std::clamp(std::floor((t - range[0]) / span * (r - 1)), 0.0, double(r - 2));
      const double a = std::clamp(range[0] + span * j / (r - 1), 0.0, 1.0);
      const double b = std::clamp(range[0] + span * (j + 1) / (r - 1), 0.0, 1.0);
      from[s] = a * (samples - 1), to[s] = b * (samples - 1);
      weight[s] = b > a ? (t - a) / (b - a) : 0.0;
    }
    for (size_t m = 0; m < movers.size(); ++m) {
      const uint32_t i = movers[m];
      double far = 0;
      for (uint32_t s = 0; s < samples; ++s) {
        double d2 = 0;
        for (uint32_t k = 0; k < dims; ++k) {
          const double line = (1 - weight[s]) * at(i, from[s], k) + weight[s] * at(i, to[s], k);
          const double gap = line - paths[(size_t{s} * n + i) * dims + k];
          d2 += gap * gap;
        }
        far = std::max(far, d2);
      }
      worst[m] = static_cast<float>(std::sqrt(far));
    }
    const double error = quantile(worst, 1 - kFieldFitQuantile);
    fit.error_by_resolution[std::to_string(r)] = error;
    if (error <= tolerance) {
      chosen = r;
      break;
    }
  }
  char text[256];
  if (chosen > kFieldFitMaxVolumeShare * resolution) {
    std::snprintf(text, sizeof text,
                  chosen == resolution
                      ? "the paths of the %u moving Gaussians need more than %u of the %u time texels: the time axis stays"
                      : "the paths of the %u moving Gaussians need %u of the %u time texels (more than %.0f %%): the time axis stays",
                  fit.moving, chosen == resolution ? last : chosen, resolution, 100 * kFieldFitMaxVolumeShare);
    fit.why = text;
    return fit;
  }
  fit.fitted = true, fit.resolution = chosen;
  std::snprintf(text, sizeof text,
                "%u time texels (were %u) follow the paths of the %u moving Gaussians within %.3g (%.0fth percentile: %.3g)",
                chosen, resolution, fit.moving, tolerance, 100 * (1 - kFieldFitQuantile),
                fit.error_by_resolution[std::to_string(chosen)].get<double>());
  fit.why = text;
  return fit;
}

uint32_t field_fit_step(const run::TrainConfig& config) {
  if (config.field_fit <= 0 || config.fine_iterations == 0) return 0;
  const double share = config.fine_time_ramp + config.field_fit * (1 - config.fine_time_ramp);
  const auto open = static_cast<uint32_t>(std::ceil(config.fine_time_ramp * config.fine_iterations - 1e-9));
  return std::max({1u, open, static_cast<uint32_t>(std::lround(share * config.fine_iterations))});
}

}  // namespace s4d::train
