#include "optical_flow.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace s4d::frame_stylizers::detail {

namespace {

cv::Mat gray8(const cv::Mat& rgb) {
  cv::Mat gray, out;
  cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
  gray.convertTo(out, CV_8U, 255.0);
  return out;
}

cv::Mat dis_flow(const cv::Mat& from, const cv::Mat& to) {
  cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
  cv::Mat flow;
  dis->calc(from, to, flow);
  return flow;
}

cv::Mat sample_map(const cv::Mat& back) {
  cv::Mat map(back.size(), CV_32FC2);
  for (int y = 0; y < back.rows; ++y) {
    const cv::Vec2f* b = back.ptr<cv::Vec2f>(y);
    cv::Vec2f* m = map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < back.cols; ++x) m[x] = cv::Vec2f(static_cast<float>(x) + b[x][0], static_cast<float>(y) + b[x][1]);
  }
  return map;
}

}  // namespace

cv::Mat warp_previous(const cv::Mat& previous, const cv::Mat& back) {
  cv::Mat out;
  cv::remap(previous, out, sample_map(back), cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

Motion motion_to_previous(const cv::Mat& current, const cv::Mat& previous) {
  const cv::Mat cur = gray8(current), prev = gray8(previous);
  Motion m;
  m.back = dis_flow(cur, prev);
  const cv::Mat forward_at_landing = warp_previous(dis_flow(prev, cur), m.back);
  m.consistent.create(current.size(), CV_32F);
  for (int y = 0; y < current.rows; ++y) {
    const cv::Vec2f* b = m.back.ptr<cv::Vec2f>(y);
    const cv::Vec2f* f = forward_at_landing.ptr<cv::Vec2f>(y);
    float* ok = m.consistent.ptr<float>(y);
    for (int x = 0; x < current.cols; ++x) {
      const float lx = static_cast<float>(x) + b[x][0], ly = static_cast<float>(y) + b[x][1];
      const bool inside = lx >= 0 && ly >= 0 && lx <= static_cast<float>(current.cols - 1) &&
                          ly <= static_cast<float>(current.rows - 1);
      const cv::Vec2f sum = b[x] + f[x];
      const bool agree = sum.dot(sum) <= 0.01f * (b[x].dot(b[x]) + f[x].dot(f[x])) + 0.5f;
      ok[x] = inside && agree ? 1.0f : 0.0f;
    }
  }
  return m;
}

}  // namespace s4d::frame_stylizers::detail
