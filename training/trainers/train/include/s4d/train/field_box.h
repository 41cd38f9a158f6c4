// The deformation field's box, and its time axis, fitted to what moves (TrainConfig::field_fit). A field starts over
// the initial cloud's bounds, which on most captures are far larger than what moves: a random
// initial cloud fills a box around the object, a room's walls stand still around the few things
// that move. Its planes then spend most of their texels where nothing moves. Once the field has
// trained for a while, the Gaussians' paths over time tell what moves and where; the box shrinks to
// those paths (padded), each axis keeps its texel size (so it needs fewer texels), and the planes
// are resampled onto it (deform/field_resample.h): the motion is resolved as finely as before with
// fewer parameters. Written to train.json dataset.recipe.field_box (and field_time, below).
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "s4d/run/train_config.h"

namespace s4d::train {

// The box is refitted only when it shrinks to at most this share of the old box's volume: a smaller
// gain is not worth the resampling's blur of the trained planes.
constexpr double kFieldFitMaxVolumeShare = 0.7;
// The paths kept: the quantiles of the moving Gaussians' lowest and highest coordinates on each
// axis, so that a few floaters thrown far do not stretch the box.
constexpr double kFieldFitQuantile = 0.01;
// Padding on each side, as a share of the paths' extent, so that what the paths just miss (a
// Gaussian densified later, a limb at its extreme) still lies inside.
constexpr double kFieldFitPad = 0.1;
// Fewer moving Gaussians than this say too little about where the motion is: the box stays.
constexpr uint32_t kFieldFitMinMoving = 16;

struct FieldBox {
  bool fitted = false;
  std::array<float, 3> old_min{}, old_max{};  // the field's box before
  std::array<float, 3> min{}, max{};          // after (the old box when not fitted)
  std::array<uint32_t, 3> old_resolution{}, resolution{};  // level-0 texels per axis, before and after
  uint32_t gaussians = 0, moving = 0;
  double move_limit = 0;    // world units a Gaussian's mean must move over time to count as moving
  double volume_share = 1;  // the new box's volume over the old one's
  uint32_t at_step = 0;     // fine-stage iteration of the fit
  std::string why;
  nlohmann::json json() const;
};

// Whether Gaussian i's path, its means' range [lo, hi] (3 floats each), spans `move_limit`: what
// both the box and the time axis count as moving.
bool path_moves(std::span<const float> lo, std::span<const float> hi, size_t i, double move_limit);

// The box for Gaussians whose means range over [lo, hi] (3 floats each, over time samples) within
// the field's box [old_min, old_max] of `resolution` level-0 texels per axis; a Gaussian moves when
// its range's diagonal reaches `move_limit`. The new box: the moving paths' quantiles, padded,
// inside the old box, at least 4 old texel cells on each axis. Each axis then gets the fewest
// texels (at least S4D_DEFORM_MIN_RESOLUTION) whose cells are no larger than before. Throws
// std::invalid_argument for sizes that disagree.
FieldBox fit_field_box(std::span<const float> lo, std::span<const float> hi, const std::array<float, 3>& old_min,
                       const std::array<float, 3>& old_max, const std::array<uint32_t, 3>& resolution, double move_limit);

// The field's time axis sized to how fast things move. The planes are bilinear in time between the
// time texels, so R texels follow a path exactly where it is linear between R evenly spaced times.
// The moving Gaussians' states (Trainer::Impl::fit_time: the mean, the extents and the rotation, in
// world units) are sampled finely over the field's time range; the axis keeps the fewest texels
// whose piecewise-linear paths stay within the tolerance of the sampled ones (the motion a Gaussian
// may have and still count as still, move_limit) for all but kFieldFitQuantile of them. It is
// refitted only when that is at most kFieldFitMaxVolumeShare of the texels it has.
struct FieldTime {
  bool fitted = false;
  uint32_t old_resolution = 0, resolution = 0;  // time texels, before and after
  uint32_t moving = 0, samples = 0;
  double tolerance = 0;
  nlohmann::json error_by_resolution = nlohmann::json::object();  // texels -> the quantile's distance from the path
  uint32_t at_step = 0;  // fine-stage iteration of the fit
  std::string why;
  nlohmann::json json() const;
};

// `paths` holds `samples` (at least 2) evenly spaced times over [0, 1] (the times views have), first
// and last included, each all n Gaussians' states (`dims` floats each); `moving` flags n Gaussians
// (1: moving). The candidates' texels lie evenly over the field's time `range`; between two of them
// a path is compared with the line through its states at their times clipped to [0, 1] (a texel at
// a time no view has can continue any line). Candidates from S4D_DEFORM_MIN_RESOLUTION to
// `resolution` - 1 texels with at least two samples per texel interval. Throws
// std::invalid_argument for sizes that disagree.
FieldTime fit_field_time(std::span<const float> paths, uint32_t samples, uint32_t dims, std::span<const uint8_t> moving,
                         uint32_t resolution, const std::array<float, 2>& range, double tolerance);

// The fine-stage iteration at which the box is fitted (0: never): config.field_fit of the stage
// after its time window has opened (fine_time_ramp), never before it opens, at least 1. Before that the field has seen
// only the first frames' motion: a box fitted then leaves the later frames' paths outside it.
uint32_t field_fit_step(const run::TrainConfig& config);

}  // namespace s4d::train
