#include "s4d/synth/wave_sheet.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "s4d/synth/intersect.h"

namespace s4d::synth {
namespace {

// March steps advance at most 1/16 wavelength in x and half the amplitude in z, so between two
// samples the surface is nearly linear and the ray cannot cross it twice except at grazing angles.
// A frontal ray needs about 4 steps, a grazing one about 32 (this loop dominates render time).
constexpr double kStepsPerWavelength = 16, kStepsPerAmplitude = 2;
constexpr int kMinSteps = 2;
constexpr int kMaxRefinements = 60;
constexpr double kGapTolerance = 1e-13;

// The root of gap in [a, b], where gap changes sign, by the Illinois variant of false position:
// it keeps the bracket like bisection but converges superlinearly (a handful of sin() calls
// instead of ~50, which matters because this runs for every ray that meets the sheet).
template <typename Gap>
double refine_crossing(const Gap& gap, double a, double ga, double b, double gb) {
  int last_side = 0;
  double m = a;
  for (int i = 0; i < kMaxRefinements; ++i) {
    m = (a * gb - b * ga) / (gb - ga);
    const double gm = gap(m);
    if (std::abs(gm) < kGapTolerance || b - a < kGapTolerance) break;
    if ((gm <= 0) == (ga <= 0)) {
      a = m, ga = gm;
      if (last_side == -1) gb *= 0.5;  // the same end moved twice: halve the other's weight
      last_side = -1;
    } else {
      b = m, gb = gm;
      if (last_side == 1) ga *= 0.5;
      last_side = 1;
    }
  }
  return m;
}

}  // namespace

double WaveSheet::depth(double x, double t) const {
  const double u = (x - x0) / (x1 - x0);
  return z0 + amplitude * u * std::sin(2 * std::numbers::pi * ((x - x0) / wavelength - t));
}

double WaveSheet::slope(double x, double t) const {
  const double u = (x - x0) / (x1 - x0);
  const double phase = 2 * std::numbers::pi * ((x - x0) / wavelength - t);
  return amplitude * (std::sin(phase) / (x1 - x0) + u * std::cos(phase) * 2 * std::numbers::pi / wavelength);
}

Vec3 WaveSheet::normal(double x, double t) const { return normalize(Vec3{-slope(x, t), 0, 1}); }

std::optional<double> intersect_wave_sheet(const Ray& ray, const WaveSheet& sheet, double t, double s_min,
                                           double s_max) {
  const auto span = clip_to_box(ray, {sheet.x0, sheet.y0, sheet.z0 - sheet.amplitude},
                                {sheet.x1, sheet.y1, sheet.z0 + sheet.amplitude}, s_min, s_max);
  if (!span) return std::nullopt;
  const auto gap = [&](double s) {
    const Vec3 p = ray.at(s);
    return p[2] - sheet.depth(p[0], t);
  };
  const double length = span->second - span->first;
  const double steps_x = std::abs(ray.dir[0]) * length / sheet.wavelength * kStepsPerWavelength;
  const double steps_z = std::abs(ray.dir[2]) * length / sheet.amplitude * kStepsPerAmplitude;
  const int steps = std::max(kMinSteps, static_cast<int>(std::ceil(std::max(steps_x, steps_z))));
  const double step = length / steps;
  double a = span->first, ga = gap(a);
  for (int k = 1; k <= steps; ++k) {
    const double b = span->first + step * k, gb = gap(b);
    if ((ga <= 0) != (gb <= 0)) {
      const double s = refine_crossing(gap, a, ga, b, gb);
      if (s > s_min && s < s_max) return s;
      return std::nullopt;
    }
    a = b, ga = gb;
  }
  return std::nullopt;
}

}  // namespace s4d::synth
