// Growth that follows missing content: where a training view's render misses its ground truth and
// does not cover the pixel, new Gaussians are seeded on the pixel's ray. A monocular capture sees a moving object in another
// place in every frame, so a fit fades it and gradient-driven growth, which only splits what is
// already there, never brings it back; seeding puts Gaussians where the object is in that frame.
// The depth on the ray is the one whose projections into other views (the same time's other
// cameras on a rig, the nearest times' on a monocular capture) agree best with the pixel's colour,
// a plane sweep over the ray's segment inside the scene's box, or where the sweep finds none the
// render's own under a faint cover. A pixel the model covers has wrong colour, not missing
// geometry, and is left to gradient-driven growth. CPU only: the trainer renders.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "s4d/io/image_io.h"
#include "s4d/io/nerf_cameras.h"

namespace s4d::train {

struct SeedSettings {
  // Mean absolute error over the channels above which a pixel is missed content: a quarter of the
  // range, well above what a model still learning leaves (the built-in scene's test views have a
  // mean error of 0.02-0.04 at 28 dB).
  float error_threshold = 0.25f;
  uint32_t cell = 4;             // at most one seed per cell x cell pixels (the worst)
  uint32_t max_seeds = 256;      // per view
  uint32_t depth_samples = 64;   // along the ray's segment inside the box
  float covered_alpha = 0.5f;    // the render covers a pixel from this alpha on: nothing is missed there
  float faint_alpha = 0.1f;      // from this alpha on, the render's depth stands in for a failed sweep
  float distinct = 0.5f;         // the sweep's best cost must be at most this times the ray's mean
};

struct ViewImage {
  const io::ImageF* image = nullptr;  // [H, W, 3] ground truth
  io::CameraView camera;
};

struct Seed {
  std::array<float, 3> position{}, colour{};
  float scale = 0;  // world units: the cell's footprint at the seed's depth
  uint32_t x = 0, y = 0;
  float error = 0;
  bool from_render_depth = false;
};

struct RenderedView {
  const io::ImageF* rgb = nullptr;   // [H, W, 3]
  const std::vector<float>* alpha = nullptr;  // [H, W]
  const std::vector<float>* depth = nullptr;  // [H, W]: sum of depth x weight (divide by alpha)
};

// The missed pixels of `truth`, worst first, one per cell, at most max_seeds.
struct MissedPixel {
  uint32_t x = 0, y = 0;
  float error = 0;
};
std::vector<MissedPixel> missed_pixels(const io::ImageF& render, const io::ImageF& truth, const SeedSettings& s);

// The depth along pixel (x, y)'s ray of `source` whose projections into `others` agree best with
// the pixel's colour (bilinear 3x3 means, mean absolute difference; a view the point falls outside
// of counts as a difference of s.error_threshold); nullopt when no depth inside the box is seen by
// half the others, the best disagrees by more than s.error_threshold, or it is not below
// s.distinct times the mean over the ray.
std::optional<double> consistent_depth(const ViewImage& source, double x, double y, const std::vector<ViewImage>& others,
                                       const std::array<float, 3>& box_lo, const std::array<float, 3>& box_hi,
                                       const SeedSettings& s);

// Seeds for one view: its missed pixels the render covers with alpha below covered_alpha, each
// placed by consistent_depth or, failing that, at the render's depth under a cover of at least
// faint_alpha (pixels placed by neither are skipped).
std::vector<Seed> find_missing_content(const ViewImage& source, const RenderedView& render, const std::vector<ViewImage>& others,
                                       const std::array<float, 3>& box_lo, const std::array<float, 3>& box_hi,
                                       const SeedSettings& s);

}  // namespace s4d::train
