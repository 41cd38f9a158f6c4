// The non-rigid surface: a flag-like sheet pinned along its left edge, a height field over the
// (x, y) rectangle [x0, x1] x [y0, y1] whose depth travels as a wave,
//   z(x, t) = z0 + amplitude * (x - x0) / (x1 - x0) * sin(2 pi ((x - x0) / wavelength - t)).
// The amplitude grows from 0 at the pole so the motion is a deformation, not a translation.
#pragma once
#include <optional>

#include "s4d/synth/ray.h"

namespace s4d::synth {

struct WaveSheet {
  double x0 = -0.5, x1 = 1.5, y0 = 0.2, y1 = 1.2, z0 = -1.2;
  double amplitude = 0.2, wavelength = 1.0;

  double depth(double x, double t) const;  // z(x, t)
  double slope(double x, double t) const;  // dz/dx
  // Unit normal facing +z (flip it for rays from behind).
  Vec3 normal(double x, double t) const;
};

// Nearest crossing with s in (s_min, s_max): the ray is clipped to the sheet's bounding box,
// marched in short steps until z - z(x, t) changes sign, then the crossing is bisected to double
// precision. A ray crossing twice within one step (only possible at grazing angles) may miss.
std::optional<double> intersect_wave_sheet(const Ray& ray, const WaveSheet& sheet, double t, double s_min,
                                           double s_max);

}  // namespace s4d::synth
