#include "s4d/frame_stylizers/warp_error.h"

#include <limits>
#include <stdexcept>
#include <string>

#include "cv_image.h"
#include "optical_flow.h"

namespace s4d::frame_stylizers {

double warp_error(const std::vector<io::ImageF>& content, const std::vector<io::ImageF>& frames) {
  if (content.size() < 2 || frames.size() != content.size())
    throw std::invalid_argument("warp_error: needs at least 2 content frames and as many frames (got " +
                                std::to_string(content.size()) + " and " + std::to_string(frames.size()) + ")");
  for (size_t t = 0; t < content.size(); ++t)
    if (content[t].channels != 3 || frames[t].channels != 3 || content[t].width != content[0].width ||
        content[t].height != content[0].height || frames[t].width != content[0].width ||
        frames[t].height != content[0].height)
      throw std::invalid_argument("warp_error: frame " + std::to_string(t) + " is not RGB of the first content frame's size");
  double sum = 0, count = 0;
  for (size_t t = 1; t < content.size(); ++t) {
    const detail::Motion motion = detail::motion_to_previous(detail::mat_copy(content[t]), detail::mat_copy(content[t - 1]));
    const cv::Mat warped = detail::warp_previous(detail::mat_copy(frames[t - 1]), motion.back);
    const cv::Mat now = detail::mat_copy(frames[t]);
    for (int y = 0; y < now.rows; ++y) {
      const cv::Vec3f* a = now.ptr<cv::Vec3f>(y);
      const cv::Vec3f* b = warped.ptr<cv::Vec3f>(y);
      const float* ok = motion.consistent.ptr<float>(y);
      for (int x = 0; x < now.cols; ++x) {
        if (ok[x] == 0.0f) continue;
        for (int k = 0; k < 3; ++k) sum += std::abs(static_cast<double>(a[x][k]) - b[x][k]);
        count += 3;
      }
    }
  }
  return count > 0 ? sum / count : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace s4d::frame_stylizers
