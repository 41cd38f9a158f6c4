#include "patch_bank.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

#include "dense_math.h"

namespace s4d::frame_stylizers::detail {

namespace {

constexpr int kDescriptorGrid = 7;  // g: descriptor samples per side
constexpr int kPcaSamples = 1000;   // patches the PCA is fitted on

}  // namespace

void copy_patch(const cv::Mat& image, int x, int y, int n, float* out) {
  const size_t row_bytes = static_cast<size_t>(n) * 3 * sizeof(float);
  for (int dy = 0; dy < n; ++dy) std::memcpy(out + static_cast<size_t>(dy) * n * 3, image.ptr<float>(y + dy) + 3 * x, row_bytes);
}

PatchBank::PatchBank(const cv::Mat& style, int patch_size, int max_patches, int pca_dims)
    : n_(patch_size), g_(std::min(patch_size, kDescriptorGrid)) {
  if (style.type() != CV_32FC3 || !style.isContinuous() || patch_size < 1 || style.cols < patch_size ||
      style.rows < patch_size || max_patches < 1 || pca_dims < 1)
    throw std::invalid_argument("PatchBank: a " + std::to_string(style.cols) + "x" + std::to_string(style.rows) +
                                " style cannot hold " + std::to_string(patch_size) + "-pixel patches");
  const int span_x = style.cols - n_ + 1, span_y = style.rows - n_ + 1;
  int stride = 1;
  while (((span_x + stride - 1) / stride) * ((span_y + stride - 1) / stride) > max_patches) ++stride;
  std::vector<cv::Point> corners;
  for (int y = 0; y < span_y; y += stride)
    for (int x = 0; x < span_x; x += stride) corners.emplace_back(x, y);
  patches_.create(static_cast<int>(corners.size()), n_ * n_ * 3, CV_32F);
  for (int i = 0; i < patches_.rows; ++i) copy_patch(style, corners[i].x, corners[i].y, n_, patches_.ptr<float>(i));

  const cv::Mat all = descriptors(style, corners);
  const int samples = std::min(kPcaSamples, all.rows);
  cv::Mat sample(samples, all.cols, CV_32F);
  for (int s = 0; s < samples; ++s) all.row(static_cast<int>(static_cast<int64_t>(s) * all.rows / samples)).copyTo(sample.row(s));
  const cv::PCA pca(sample, cv::noArray(), cv::PCA::DATA_AS_ROW, std::min({pca_dims, all.cols, samples}));
  mean_ = pca.mean;
  basis_ = pca.eigenvectors;
  reduced_ = times_transposed(all - cv::repeat(mean_, all.rows, 1), basis_);
  sq_norms_.resize(static_cast<size_t>(reduced_.rows));
  for (int i = 0; i < reduced_.rows; ++i) sq_norms_[static_cast<size_t>(i)] = static_cast<float>(reduced_.row(i).dot(reduced_.row(i)));
}

cv::Mat PatchBank::descriptors(const cv::Mat& image, const std::vector<cv::Point>& corners) const {
  // Box cells of about n / g pixels, sampled at the centres of a g x g grid over the patch.
  const int box = std::max(1, (n_ + g_ / 2) / g_);
  cv::Mat low;
  cv::boxFilter(image, low, CV_32F, cv::Size(box, box), cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  std::vector<int> offset(static_cast<size_t>(g_));
  for (int i = 0; i < g_; ++i) offset[static_cast<size_t>(i)] = (2 * i + 1) * n_ / (2 * g_);
  cv::Mat out(static_cast<int>(corners.size()), g_ * g_ * 3, CV_32F);
  for (int r = 0; r < out.rows; ++r) {
    float* d = out.ptr<float>(r);
    for (int gy = 0; gy < g_; ++gy) {
      const float* row = low.ptr<float>(corners[r].y + offset[static_cast<size_t>(gy)]);
      for (int gx = 0; gx < g_; ++gx, d += 3) std::memcpy(d, row + 3 * (corners[r].x + offset[static_cast<size_t>(gx)]), 3 * sizeof(float));
    }
  }
  return out;
}

std::vector<int> PatchBank::nearest(const cv::Mat& image, const std::vector<cv::Point>& corners) const {
  for (const cv::Point& c : corners)
    if (c.x < 0 || c.y < 0 || c.x + n_ > image.cols || c.y + n_ > image.rows)
      throw std::invalid_argument("PatchBank::nearest: a patch lies outside the image");
  const cv::Mat d = descriptors(image, corners);
  const cv::Mat q = times_transposed(d - cv::repeat(mean_, d.rows, 1), basis_);
  return nearest_rows(q, reduced_, sq_norms_);
}

}  // namespace s4d::frame_stylizers::detail
