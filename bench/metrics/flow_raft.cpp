#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <stdexcept>

#include "s4d/metrics/flow.h"
#include "s4d/metrics/image_checks.h"

namespace s4d::metrics {

namespace {

// RAFT's InputPadder: each side padded to a multiple of 8, the padding split evenly, edge replicated.
struct Padding {
  int left, right, top, bottom;
};

Padding padding_for(int w, int h) {
  const int pw = (8 - w % 8) % 8, ph = (8 - h % 8) % 8;
  return {pw / 2, pw - pw / 2, ph / 2, ph - ph / 2};
}

cv::Mat blob_of(const io::ImageF& rgb, const Padding& p) {
  cv::Mat f(rgb.height, rgb.width, CV_32FC3, const_cast<float*>(rgb.data.data())), scaled, padded;
  f.convertTo(scaled, CV_32FC3, 255.0);
  cv::copyMakeBorder(scaled, padded, p.top, p.bottom, p.left, p.right, cv::BORDER_REPLICATE);
  return cv::dnn::blobFromImage(padded);  // NCHW, channel order kept (RGB), no scaling
}

}  // namespace

struct RaftFlow::Net {
  cv::dnn::Net net;
};

RaftFlow::RaftFlow(const std::filesystem::path& onnx, std::pair<std::string, std::string> input_names)
    : inputs_(std::move(input_names)), path_(onnx) {
  if (!std::filesystem::is_regular_file(onnx))
    throw std::runtime_error(onnx.string() +
                             ": RAFT ONNX model not found (export RAFT, e.g. raft-things.pth, to ONNX and pass its path)");
  try {
    net_ = std::make_unique<Net>(Net{cv::dnn::readNetFromONNX(onnx.string())});
  } catch (const cv::Exception& e) {
    throw std::runtime_error(onnx.string() + ": OpenCV cannot load the RAFT ONNX model: " + e.what());
  }
  if (net_->net.empty()) throw std::runtime_error(onnx.string() + ": OpenCV loaded an empty network");
}

RaftFlow::~RaftFlow() = default;

Flow RaftFlow::operator()(const io::ImageF& from, const io::ImageF& to) {
  require_same_rgb(from, to, "raft flow");
  const Padding p = padding_for(from.width, from.height);
  cv::Mat out;
  try {
    net_->net.setInput(blob_of(from, p), inputs_.first);
    net_->net.setInput(blob_of(to, p), inputs_.second);
    out = net_->net.forward();
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path_.string() + ": RAFT inference failed (inputs '" + inputs_.first + "', '" +
                             inputs_.second + "'): " + e.what());
  }
  const int hp = from.height + p.top + p.bottom, wp = from.width + p.left + p.right;
  if (out.dims != 4 || out.size[0] != 1 || out.size[1] != 2 || out.size[2] != hp || out.size[3] != wp)
    throw std::runtime_error(path_.string() + ": RAFT's first output is not the flow [1, 2, " + std::to_string(hp) +
                             ", " + std::to_string(wp) + "]");
  Flow f{from.width, from.height, std::vector<float>(size_t(from.width) * size_t(from.height) * 2)};
  const float* u = out.ptr<float>(0, 0);
  const float* v = out.ptr<float>(0, 1);
  for (int y = 0; y < from.height; ++y)
    for (int x = 0; x < from.width; ++x) {
      const size_t src = size_t(y + p.top) * wp + size_t(x + p.left), dst = size_t(y) * from.width + x;
      f.uv[dst * 2] = u[src];
      f.uv[dst * 2 + 1] = v[src];
    }
  return f;
}

}  // namespace s4d::metrics
