#include "s4d/bench/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace s4d::bench {

namespace {
constexpr int kLabelWidth = 160, kHeader = 24;
}

io::ImageF contact_sheet(const std::vector<SheetRow>& rows, const std::vector<int>& frame_index, int tile_width) {
  if (rows.empty() || rows[0].frames.empty()) throw std::invalid_argument("contact_sheet: no frames");
  const size_t cols = rows[0].frames.size();
  for (const auto& r : rows)
    if (r.frames.size() != cols || frame_index.size() != cols)
      throw std::invalid_argument("contact_sheet: row '" + r.label + "' has " + std::to_string(r.frames.size()) +
                                  " frames, expected " + std::to_string(cols));
  const io::ImageF& first = rows[0].frames[0];
  const int tile_h = std::max(1, int(std::lround(double(tile_width) * first.height / first.width)));
  const int w = kLabelWidth + int(cols) * tile_width, h = kHeader + int(rows.size()) * tile_h;
  cv::Mat sheet(h, w, CV_32FC3, cv::Scalar(1, 1, 1));
  const cv::Scalar black(0, 0, 0);
  for (size_t c = 0; c < cols; ++c)
    cv::putText(sheet, "frame " + std::to_string(frame_index[c]), {kLabelWidth + int(c) * tile_width + 6, 17},
                cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
  for (size_t r = 0; r < rows.size(); ++r) {
    const int top = kHeader + int(r) * tile_h;
    cv::putText(sheet, rows[r].label.substr(0, 18), {6, top + tile_h / 2}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
    for (size_t c = 0; c < cols; ++c) {
      const io::ImageF& f = rows[r].frames[c];
      cv::Mat src(f.height, f.width, CV_32FC3, const_cast<float*>(f.data.data())), tile;
      cv::resize(src, tile, {tile_width, tile_h}, 0, 0, cv::INTER_AREA);
      tile.copyTo(sheet(cv::Rect(kLabelWidth + int(c) * tile_width, top, tile_width, tile_h)));
    }
  }
  io::ImageF out{w, h, 3, {}};
  out.data.assign(sheet.ptr<float>(), sheet.ptr<float>() + sheet.total() * 3);
  return out;
}

}  // namespace s4d::bench
