#include "dense_math.h"

#include <stdexcept>
#include <string>

namespace s4d::frame_stylizers::detail {

namespace {

// Eight partial sums, so the compiler vectorises without reassociating one sum (no -ffast-math).
float dot(const float* a, const float* b, int n) {
  float part[8] = {};
  int i = 0;
  for (; i + 8 <= n; i += 8)
    for (int j = 0; j < 8; ++j) part[j] += a[i + j] * b[i + j];
  float sum = ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
  for (; i < n; ++i) sum += a[i] * b[i];
  return sum;
}

void check(const cv::Mat& a, const cv::Mat& b, const char* what) {
  if (a.type() != CV_32F || b.type() != CV_32F || a.cols != b.cols || !a.isContinuous() || !b.isContinuous())
    throw std::invalid_argument(std::string(what) + ": needs continuous CV_32F matrices with equal column counts");
}

}  // namespace

cv::Mat times_transposed(const cv::Mat& a, const cv::Mat& b) {
  check(a, b, "times_transposed");
  cv::Mat out(a.rows, b.rows, CV_32F);
  cv::parallel_for_(cv::Range(0, a.rows), [&](const cv::Range& rows) {
    for (int r = rows.start; r < rows.end; ++r) {
      float* o = out.ptr<float>(r);
      for (int c = 0; c < b.rows; ++c) o[c] = dot(a.ptr<float>(r), b.ptr<float>(c), a.cols);
    }
  });
  return out;
}

std::vector<int> nearest_rows(const cv::Mat& queries, const cv::Mat& points, const std::vector<float>& sq_norms) {
  check(queries, points, "nearest_rows");
  if (points.rows == 0 || sq_norms.size() != static_cast<size_t>(points.rows))
    throw std::invalid_argument("nearest_rows: needs at least one point and one norm per point");
  std::vector<int> best(static_cast<size_t>(queries.rows));
  cv::parallel_for_(cv::Range(0, queries.rows), [&](const cv::Range& rows) {
    for (int r = rows.start; r < rows.end; ++r) {
      const float* q = queries.ptr<float>(r);
      int arg = 0;
      float low = sq_norms[0] - 2 * dot(q, points.ptr<float>(0), points.cols);
      for (int c = 1; c < points.rows; ++c) {
        const float v = sq_norms[static_cast<size_t>(c)] - 2 * dot(q, points.ptr<float>(c), points.cols);
        if (v < low) low = v, arg = c;
      }
      best[static_cast<size_t>(r)] = arg;
    }
  });
  return best;
}

}  // namespace s4d::frame_stylizers::detail
