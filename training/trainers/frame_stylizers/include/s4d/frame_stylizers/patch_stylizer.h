// The weight-free default stylizer ("patch"): Elad & Milanfar 2017, "Style Transfer via Texture
// Synthesis" (IEEE TIP 26(5)), with a temporal warm start for video.
//
// Per frame, coarse to fine over `scales` levels (factor 2), starting from the content colour-
// transferred to the style's palette plus Gaussian noise, and for each patch size (largest first)
// `iterations` times:
//   (a) nearest style patch of every content patch (a grid with a seeded random offset), searched
//       by brute force over PCA-reduced patch vectors of the style at the same scale;
//   (b) robust aggregation of the matched patches by IRLS with r = 0.8 (robust_aggregation.h);
//   (c) content fusion X = (X~ + W C) / (1 + W), with W a weight map that is larger on the
//       content's edges (smoothed gradient magnitude), so outlines survive and flat regions take
//       the style's texture;
//   (d) colour transfer of X to the style's palette (per-channel histogram matching);
//   (e) denoising with an edge-preserving bilateral filter.
// Video: frame t > 0 starts at the finest scale from frame t - 1's result warped by DIS optical flow
// computed on the content (backward flow t -> t - 1); pixels failing the forward-backward check start
// from the colour-transferred content instead. It then runs `video_iterations` per patch size at the
// finest scale only, with the warped frame as an extra fusion term on consistent pixels, so the
// sequence does not flicker.
#pragma once
#include <vector>

#include "s4d/frame_stylizers/stylizer.h"

namespace s4d::frame_stylizers {

struct PatchStylizerOptions {
  int scales = 3;      // pyramid levels, factor 2 between them
  int iterations = 3;  // per patch size and scale (the paper's 3)
  int video_iterations = 1;  // per patch size at the finest scale, frames t > 0
  int irls_iterations = 3;
  // Patch sizes for a frame whose short side is kReferenceShortSide; other sizes scale them in
  // proportion (rounded to odd, at least 5). The paper's 33/21/13 were for 400 px images with a
  // coarsest level of 100 px; 200 px keeps the same stroke size relative to the frame at our
  // smaller training frames (160x120 -> 19, 13, 7).
  std::vector<int> patch_sizes = {33, 21, 13};
  static constexpr int kReferenceShortSide = 200;
  int pca_dims = 24;  // patch vectors are compared in this many principal components
  int max_style_patches = 4000;  // per scale and size; the style grid's stride grows to fit
  float noise_sigma = 0.2f;      // initial noise on the coarsest level (the paper's 50 of 255)
  float content_weight = 0.8f;   // W on the strongest content edges
  float content_floor = 0.03f;   // W in flat regions
  float temporal_weight = 4.0f;  // fusion weight of the warped previous frame (video)
};

class PatchStylizer final : public Stylizer {
 public:
  explicit PatchStylizer(PatchStylizerOptions options = {});
  std::string name() const override { return "patch"; }
  std::vector<io::ImageF> stylize(const std::vector<io::ImageF>& frames, const io::ImageF& style,
                                  const StylizeSettings& settings,
                                  const FrameProgressFn& progress = {}) const override;

 private:
  PatchStylizerOptions options_;
};

}  // namespace s4d::frame_stylizers
