// The patch stylizer's driver: style set-up (palette, pyramid, patch banks), the per-level
// refinement loop of Elad & Milanfar (steps (a)-(e), see patch_stylizer.h) and the video warm start.
#include "s4d/frame_stylizers/patch_stylizer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "content_weight.h"
#include "cv_image.h"
#include "optical_flow.h"
#include "palette.h"
#include "patch_bank.h"
#include "s4d/frame_stylizers/robust_aggregation.h"

namespace s4d::frame_stylizers {

namespace {

using detail::PatchBank;

// A patch size must leave room for a few positions on the level's short side: at most this fraction.
constexpr double kMaxPatchFraction = 0.8;
// Bilateral denoising (step (e)): 5-pixel window, range sigma 0.08 (about 20 levels of 255) removes
// the aggregation's seams and keeps stroke edges; a spatial sigma of 2 pixels.
constexpr int kDenoiseDiameter = 5;
constexpr double kDenoiseSigmaRange = 0.08, kDenoiseSigmaSpace = 2.0;

struct Level {
  cv::Size size;
  std::vector<PatchBank> banks;  // largest patches first
};

struct StyleSetup {
  detail::Palette palette;
  std::vector<Level> levels;  // [0] is the frame's size; only levels with at least one bank
};

struct Temporal {
  cv::Mat warped;  // the previous result moved to this frame
  cv::Mat mask;    // 1 where the motion is consistent
};

int odd_size(double v) { return std::max(5, 2 * static_cast<int>(std::lround((v - 1.0) / 2.0)) + 1); }

uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

cv::Mat resized(const cv::Mat& image, cv::Size size) {
  if (image.size() == size) return image.clone();
  cv::Mat out;
  const bool shrink = size.width < image.cols || size.height < image.rows;
  cv::resize(image, out, size, 0, 0, shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
  return out;
}

std::vector<int> frame_patch_sizes(const PatchStylizerOptions& o, cv::Size frame) {
  const double scale = static_cast<double>(std::min(frame.width, frame.height)) / PatchStylizerOptions::kReferenceShortSide;
  std::vector<int> sizes;
  for (int n : o.patch_sizes) sizes.push_back(odd_size(n * scale));
  std::sort(sizes.rbegin(), sizes.rend());
  sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
  return sizes;
}

StyleSetup prepare_style(const cv::Mat& style, cv::Size frame, const PatchStylizerOptions& o) {
  // The style is scaled so its short side matches the frame's: strokes keep their size relative to
  // the frame whatever the two resolutions are.
  const double factor = static_cast<double>(std::min(frame.width, frame.height)) / std::min(style.cols, style.rows);
  const cv::Size style_size(std::max(1, static_cast<int>(std::lround(style.cols * factor))),
                            std::max(1, static_cast<int>(std::lround(style.rows * factor))));
  const cv::Mat style0 = resized(style, style_size);
  StyleSetup setup{detail::Palette(style0), {}};
  const std::vector<int> sizes = frame_patch_sizes(o, frame);
  for (int l = 0; l < o.scales; ++l) {
    const double down = std::ldexp(1.0, -l);
    Level level{cv::Size(std::max(1, static_cast<int>(std::lround(frame.width * down))),
                         std::max(1, static_cast<int>(std::lround(frame.height * down)))),
                {}};
    const cv::Mat style_l = resized(style0, cv::Size(std::max(1, static_cast<int>(std::lround(style0.cols * down))),
                                                     std::max(1, static_cast<int>(std::lround(style0.rows * down)))));
    const int short_side = std::min(level.size.width, level.size.height);
    for (int n : sizes)
      if (n <= kMaxPatchFraction * short_side && n <= style_l.cols && n <= style_l.rows)
        level.banks.emplace_back(style_l, n, o.max_style_patches, o.pca_dims);
    if (level.banks.empty()) break;
    setup.levels.push_back(std::move(level));
  }
  return setup;
}

// Patch corners along one axis: every `gap` from a random offset, plus both ends, so every pixel is covered.
std::vector<int> grid(int length, int n, int gap, cv::RNG& rng) {
  std::vector<int> at;
  const int offset = rng.uniform(0, gap);
  if (offset > 0) at.push_back(0);
  for (int p = offset; p <= length - n; p += gap) at.push_back(p);
  if (at.back() != length - n) at.push_back(length - n);
  return at;
}

// Step (c): X = (X~ + W C + lambda M P) / (1 + W + lambda M).
cv::Mat fuse(const io::ImageF& aggregate, const cv::Mat& content, const cv::Mat& weight, const Temporal* temporal,
             float temporal_weight) {
  cv::Mat out(content.size(), CV_32FC3);
  for (int y = 0; y < out.rows; ++y) {
    const float* a = aggregate.data.data() + static_cast<size_t>(y) * aggregate.width * 3;
    const cv::Vec3f* c = content.ptr<cv::Vec3f>(y);
    const float* w = weight.ptr<float>(y);
    const cv::Vec3f* p = temporal ? temporal->warped.ptr<cv::Vec3f>(y) : nullptr;
    const float* m = temporal ? temporal->mask.ptr<float>(y) : nullptr;
    cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
    for (int x = 0; x < out.cols; ++x) {
      const float lm = m ? temporal_weight * m[x] : 0.0f;
      for (int k = 0; k < 3; ++k)
        o[x][k] = (a[3 * x + k] + w[x] * c[x][k] + (p ? lm * p[x][k] : 0.0f)) / (1.0f + w[x] + lm);
    }
  }
  return out;
}

class FrameRefiner {
 public:
  FrameRefiner(const StyleSetup& setup, const PatchStylizerOptions& o) : setup_(setup), o_(o) {}

  // Runs steps (a)-(e) `iterations` times per patch size of `level` on x.
  cv::Mat refine(cv::Mat x, int level, const cv::Mat& content, const cv::Mat& weight, const Temporal* temporal,
                 int iterations, cv::RNG& rng) const {
    for (const PatchBank& bank : setup_.levels[static_cast<size_t>(level)].banks) {
      const int n = bank.patch_size(), gap = std::max(2, 2 * n / 3);
      for (int it = 0; it < iterations; ++it) {
        const std::vector<int> xs = grid(x.cols, n, gap, rng), ys = grid(x.rows, n, gap, rng);
        std::vector<cv::Point> corners;
        for (int py : ys)
          for (int px : xs) corners.emplace_back(px, py);
        const std::vector<int> match = bank.nearest(x, corners);
        std::vector<PlacedPatch> placed;
        for (size_t i = 0; i < corners.size(); ++i) placed.push_back({corners[i].x, corners[i].y, bank.patch(match[i])});
        const io::ImageF aggregate =
            robust_aggregate(detail::image_from(x), n, placed, {0.8f, o_.irls_iterations, 1e-3f});
        const cv::Mat fused = setup_.palette.apply(fuse(aggregate, content, weight, temporal, o_.temporal_weight));
        cv::bilateralFilter(fused, x, kDenoiseDiameter, kDenoiseSigmaRange, kDenoiseSigmaSpace);
      }
    }
    return x;
  }

 private:
  const StyleSetup& setup_;
  const PatchStylizerOptions& o_;
};

}  // namespace

PatchStylizer::PatchStylizer(PatchStylizerOptions options) : options_(std::move(options)) {
  const auto& o = options_;
  if (o.scales < 1 || o.iterations < 1 || o.video_iterations < 0 || o.irls_iterations < 1 || o.patch_sizes.empty() ||
      o.pca_dims < 1 || o.max_style_patches < 1 || o.noise_sigma < 0 || o.content_floor < 0 ||
      o.content_weight < o.content_floor || o.temporal_weight < 0)
    throw std::invalid_argument("PatchStylizer: options out of range");
  for (int n : o.patch_sizes)
    if (n < 1) throw std::invalid_argument("PatchStylizer: patch sizes must be positive");
}

std::vector<io::ImageF> PatchStylizer::stylize(const std::vector<io::ImageF>& frames, const io::ImageF& style,
                                               const StylizeSettings& settings, const FrameProgressFn& progress) const {
  check_inputs(frames, style, settings);
  const int total = static_cast<int>(frames.size());
  if (settings.strength == 0.0f) {
    if (progress) progress(total, total);
    return frames;
  }
  const cv::Size frame_size(frames[0].width, frames[0].height);
  const StyleSetup setup = prepare_style(detail::mat_copy(style), frame_size, options_);
  const FrameRefiner refiner(setup, options_);
  const int levels = static_cast<int>(setup.levels.size());

  std::vector<io::ImageF> out;
  cv::Mat previous_content, previous_result;
  for (int t = 0; t < total; ++t) {
    cv::RNG rng(mix64(settings.seed ^ mix64(static_cast<uint64_t>(t))));
    const cv::Mat content = detail::mat_copy(frames[static_cast<size_t>(t)]);
    const cv::Mat transferred = setup.palette.apply(content);
    const cv::Mat weight = detail::content_weight(content, options_.content_floor, options_.content_weight);
    cv::Mat x;
    if (levels == 0) {
      x = transferred;  // too small for any patch: colour transfer only
    } else if (t == 0) {
      x = resized(transferred, setup.levels.back().size);
      cv::Mat noise(x.size(), CV_32FC3);
      rng.fill(noise, cv::RNG::NORMAL, 0.0, options_.noise_sigma);
      x += noise;
      for (int l = levels - 1; l >= 0; --l) {
        const cv::Size size = setup.levels[static_cast<size_t>(l)].size;
        x = refiner.refine(resized(x, size), l, resized(transferred, size), resized(weight, size), nullptr,
                           options_.iterations, rng);
      }
    } else {
      const detail::Motion motion = detail::motion_to_previous(content, previous_content);
      const Temporal temporal{detail::warp_previous(previous_result, motion.back), motion.consistent};
      x = cv::Mat(content.size(), CV_32FC3);
      for (int y = 0; y < x.rows; ++y)
        for (int i = 0; i < x.cols; ++i) {
          const float m = temporal.mask.at<float>(y, i);
          x.at<cv::Vec3f>(y, i) = m * temporal.warped.at<cv::Vec3f>(y, i) + (1.0f - m) * transferred.at<cv::Vec3f>(y, i);
        }
      x = refiner.refine(x, 0, transferred, weight, &temporal, options_.video_iterations, rng);
    }
    previous_content = content;
    previous_result = x;
    cv::Mat blended = content + settings.strength * (x - content);
    blended = cv::max(cv::min(blended, 1.0), 0.0);
    out.push_back(detail::image_from(blended));
    if (progress) progress(t + 1, total);
  }
  return out;
}

}  // namespace s4d::frame_stylizers
