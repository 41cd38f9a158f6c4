// The built-in painting: a canvas weave, then three layers of brush strokes (broad to fine) that
// follow a swirling flow field. Each stroke takes one palette colour chosen by a slowly varying
// zone field, and carries bristle streaks (per-bristle brightness across the stroke), a relief
// highlight on one side and a dry-brush fade at its end. All randomness is splitmix64 from the
// seed, so the image is the same on every platform.
#include "s4d/frame_stylizers/builtin_style.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace s4d::frame_stylizers {

namespace {

struct Rgb {
  float r, g, b;
};

// Night blues, teal, ochre, lemon, burnt orange, cream and near-black: a Post-Impressionist palette.
constexpr std::array<Rgb, 8> kPalette = {{{0.08f, 0.15f, 0.38f},
                                          {0.17f, 0.32f, 0.64f},
                                          {0.12f, 0.45f, 0.47f},
                                          {0.86f, 0.66f, 0.20f},
                                          {0.95f, 0.86f, 0.40f},
                                          {0.78f, 0.36f, 0.12f},
                                          {0.94f, 0.90f, 0.78f},
                                          {0.08f, 0.08f, 0.12f}}};

struct Layer {
  double width, length;  // in pixels at size 384
  int count;             // strokes at size 384
};
constexpr std::array<Layer, 3> kLayers = {{{22, 70, 260}, {12, 40, 700}, {6, 22, 1600}}};

uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(mix64(seed)) {}
  double uniform() { return static_cast<double>(mix64(state_++) >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  uint64_t state_;
};

struct Fields {
  std::array<double, 6> phase;
  // Stroke direction (radians) at a point: swirls over a gentle diagonal drift.
  double angle(double x, double y) const {
    return 1.9 * std::sin(0.012 * x + 1.4 * std::sin(0.010 * y + phase[0])) +
           1.3 * std::cos(0.016 * y - 0.8 * std::cos(0.013 * x + phase[1])) + phase[2];
  }
  // Colour zone in [0, 1).
  double zone(double x, double y) const {
    const double v = std::sin(0.017 * x + phase[3]) + std::sin(0.014 * y + phase[4]) +
                     0.6 * std::sin(0.025 * (x - y) + phase[5]);
    return std::clamp((v + 2.6) / 5.2, 0.0, 0.999);
  }
};

class Canvas {
 public:
  Canvas(int size, Rng& rng) : n_(size), rgb_(static_cast<size_t>(size) * size * 3) {
    for (int y = 0; y < n_; ++y)
      for (int x = 0; x < n_; ++x) {
        // Linen weave: crossing threads about 3 pixels apart plus grain.
        const double weave = 0.035 * std::sin(2.1 * x) * std::sin(2.1 * y) + rng.uniform(-0.02, 0.02);
        const Rgb base = kPalette[6];
        set(x, y, {static_cast<float>(base.r + weave), static_cast<float>(base.g + weave),
                   static_cast<float>(base.b * 0.95 + weave)});
      }
  }

  // One dab of a stroke centred at (cx, cy) with unit direction (dx, dy) and radius r.
  void dab(double cx, double cy, double dx, double dy, double r, const Rgb& colour, const std::array<float, 16>& bristles,
           double opacity) {
    const int x0 = std::max(0, static_cast<int>(cx - r)), x1 = std::min(n_ - 1, static_cast<int>(cx + r) + 1);
    const int y0 = std::max(0, static_cast<int>(cy - r)), y1 = std::min(n_ - 1, static_cast<int>(cy + r) + 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5 - cx, py = y + 0.5 - cy;
        const double d = std::hypot(px, py);
        if (d >= r) continue;
        const double across = (-dy * px + dx * py) / r;  // -1..1 across the stroke
        const size_t bristle = std::min<size_t>(15, static_cast<size_t>((across + 1.0) * 8.0));
        const double shade = 1.0 + bristles[bristle] + 0.10 * across;  // streaks and relief
        const double a = opacity * std::clamp((r - d) / 1.5, 0.0, 1.0);
        float* p = &rgb_[(static_cast<size_t>(y) * n_ + x) * 3];
        p[0] = static_cast<float>(p[0] * (1 - a) + colour.r * shade * a);
        p[1] = static_cast<float>(p[1] * (1 - a) + colour.g * shade * a);
        p[2] = static_cast<float>(p[2] * (1 - a) + colour.b * shade * a);
      }
  }

  io::ImageF image() const {
    io::ImageF out{n_, n_, 3, rgb_};
    for (float& v : out.data) v = std::clamp(v, 0.0f, 1.0f);
    return out;
  }

 private:
  void set(int x, int y, const Rgb& c) {
    float* p = &rgb_[(static_cast<size_t>(y) * n_ + x) * 3];
    p[0] = c.r, p[1] = c.g, p[2] = c.b;
  }
  int n_;
  std::vector<float> rgb_;
};

void paint_stroke(Canvas& canvas, const Fields& fields, Rng& rng, int size, double width, double length) {
  double x = rng.uniform(-0.05, 1.05) * size, y = rng.uniform(-0.05, 1.05) * size;
  const double z = std::clamp(fields.zone(x, y) + rng.uniform(-0.12, 0.12), 0.0, 0.999);
  Rgb colour = kPalette[static_cast<size_t>(z * kPalette.size())];
  const float tint = static_cast<float>(rng.uniform(0.9, 1.1));
  colour = {colour.r * tint, colour.g * tint, colour.b * tint};
  std::array<float, 16> bristles;
  for (float& b : bristles) b = static_cast<float>(rng.uniform(-0.13, 0.13));
  const double r = 0.5 * width * rng.uniform(0.7, 1.3);
  const double steps = length * rng.uniform(0.6, 1.4);
  const double bend = rng.uniform(-0.25, 0.25);  // each stroke leaves the flow a little
  for (double s = 0; s < steps; s += 1.0) {
    const double angle = fields.angle(x, y) + bend;
    const double dx = std::cos(angle), dy = std::sin(angle);
    // The brush runs dry over the last third of the stroke.
    const double paint = std::min(1.0, 3.0 * (steps - s) / steps);
    canvas.dab(x, y, dx, dy, r, colour, bristles, 0.45 * paint);
    x += dx, y += dy;
  }
}

}  // namespace

io::ImageF builtin_style(int size, uint64_t seed) {
  if (size < 32) throw std::invalid_argument("builtin_style: size " + std::to_string(size) + " is below 32");
  Rng rng(seed);
  Fields fields{};
  for (double& p : fields.phase) p = rng.uniform(0.0, 6.283185307179586);
  Canvas canvas(size, rng);
  const double scale = size / 384.0;
  for (const Layer& layer : kLayers) {
    const int count = static_cast<int>(std::lround(layer.count * scale * scale));
    for (int i = 0; i < count; ++i) paint_stroke(canvas, fields, rng, size, layer.width * scale, layer.length * scale);
  }
  return canvas.image();
}

}  // namespace s4d::frame_stylizers
