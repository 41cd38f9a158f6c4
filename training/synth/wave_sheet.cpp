#include "s4d/synth/wave_sheet.h"

#include <cmath>
#include <numbers>

#include "s4d/synth/intersect.h"

namespace s4d::synth {
namespace {

// Enough that a step (at most the box diagonal / 64, about 3 cm) is far shorter than the wavelength.
constexpr int kMarchSteps = 64;
constexpr int kBisections = 60;

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
    return p.z - sheet.depth(p.x, t);
  };
  const double step = (span->second - span->first) / kMarchSteps;
  double a = span->first, ga = gap(a);
  for (int k = 1; k <= kMarchSteps; ++k) {
    const double b = span->first + step * k, gb = gap(b);
    if ((ga <= 0) != (gb <= 0)) {
      double lo = a, hi = b;
      const bool lo_below = ga <= 0;
      for (int i = 0; i < kBisections; ++i) {
        const double m = 0.5 * (lo + hi);
        if ((gap(m) <= 0) == lo_below) lo = m;
        else hi = m;
      }
      const double s = 0.5 * (lo + hi);
      if (s > s_min && s < s_max) return s;
      return std::nullopt;
    }
    a = b, ga = gb;
  }
  return std::nullopt;
}

}  // namespace s4d::synth
