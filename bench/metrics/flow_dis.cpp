#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "s4d/metrics/flow.h"
#include "s4d/metrics/image_checks.h"

namespace s4d::metrics {

namespace {
cv::Mat gray8(const io::ImageF& rgb) {
  cv::Mat f(rgb.height, rgb.width, CV_32FC3, const_cast<float*>(rgb.data.data())), u8, g;
  f.convertTo(u8, CV_8UC3, 255.0);  // rounds and saturates
  cv::cvtColor(u8, g, cv::COLOR_RGB2GRAY);
  return g;
}
}  // namespace

Flow dis_flow(const io::ImageF& from, const io::ImageF& to) {
  require_same_rgb(from, to, "dis flow");
  cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
  cv::Mat flow;
  dis->calc(gray8(from), gray8(to), flow);
  Flow out{from.width, from.height, std::vector<float>(size_t(from.width) * size_t(from.height) * 2)};
  for (int y = 0; y < flow.rows; ++y)
    for (int x = 0; x < flow.cols; ++x) {
      const cv::Vec2f v = flow.at<cv::Vec2f>(y, x);
      out.uv[(size_t(y) * from.width + x) * 2] = v[0];
      out.uv[(size_t(y) * from.width + x) * 2 + 1] = v[1];
    }
  return out;
}

}  // namespace s4d::metrics
