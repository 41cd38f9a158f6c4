// The style's patches of one size at one scale, and the nearest-neighbour search over them (Elad &
// Milanfar's step (a)). Patches are taken on a regular grid whose stride grows until at most
// `max_patches` remain. They are compared by a descriptor: the patch low-passed by a box filter and
// sampled on a g x g grid (g = min(n, 7)), reduced to its leading principal components (PCA fitted
// on a deterministic subsample). The leading components of image patches are low-frequency anyway,
// and the descriptor makes the PCA fit and projections about (n / g)^2 times cheaper: 33 x 33 x 3 =
// 3267 values become 147. The search is brute force: |q|^2 is the same for every candidate, so the
// nearest is the arg-min of |s|^2 - 2 q.s.
#pragma once
#include <vector>

#include <opencv2/core.hpp>

namespace s4d::frame_stylizers::detail {

// Copies the n x n patch at (x, y) of a continuous CV_32FC3 image into `out` ([n, n, 3] row-major).
void copy_patch(const cv::Mat& image, int x, int y, int n, float* out);

class PatchBank {
 public:
  // style: continuous CV_32FC3 with both sides >= patch_size. Throws std::invalid_argument otherwise.
  PatchBank(const cv::Mat& style, int patch_size, int max_patches, int pca_dims);

  int patch_size() const { return n_; }
  const float* patch(int index) const { return patches_.ptr<float>(index); }

  // The index of the nearest style patch of each n x n patch of `image` (continuous CV_32FC3) with
  // top-left corner in `corners`.
  std::vector<int> nearest(const cv::Mat& image, const std::vector<cv::Point>& corners) const;

 private:
  cv::Mat descriptors(const cv::Mat& image, const std::vector<cv::Point>& corners) const;  // [m, g * g * 3]

  int n_, g_;
  cv::Mat patches_;   // [count, n * n * 3]
  cv::Mat mean_;      // [1, g * g * 3]
  cv::Mat basis_;     // [k, g * g * 3], rows are principal axes
  cv::Mat reduced_;   // [count, k]
  std::vector<float> sq_norms_;  // [count], |reduced row|^2
};

}  // namespace s4d::frame_stylizers::detail
