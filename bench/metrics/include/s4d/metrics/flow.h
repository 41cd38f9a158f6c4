// Optical flow fields for the warp loss: flow(x) maps pixel x of frame t to x + flow(x) in frame
// t+1 (pixels; u to the right, v down). Three sources: exact flow supplied by the caller (for
// example the renderer's, read from EXR), OpenCV DIS (weight-free) and RAFT through OpenCV DNN.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::metrics {

struct Flow {
  int width = 0, height = 0;
  std::vector<float> uv;  // [H, W, 2] row-major
};

// A flow EXR: channels "u" and "v" (pixels) over the image. Throws std::runtime_error naming the file
// when it cannot be read or lacks a channel.
Flow read_flow_exr(const std::filesystem::path& path);

// OpenCV DIS (cv::DISOpticalFlow, PRESET_MEDIUM: patch 8, finest scale 1, stride 3, variational
// refinement on) on the frames as 8-bit gray (cv::COLOR_RGB2GRAY). Frame sizes must match.
Flow dis_flow(const io::ImageF& from, const io::ImageF& to);

// RAFT exported to ONNX, run by OpenCV DNN. Inputs as RAFT's demo feeds them: RGB 0..255 float NCHW,
// padded to multiples of 8 by edge replication split evenly (RAFT's InputPadder, 'sintel' mode); the
// first output must be the final flow [1, 2, H, W], which is cropped back.
class RaftFlow {
 public:
  // `input_names`: the ONNX graph's two image inputs (first frame, second frame). Throws
  // std::runtime_error naming the file when it does not exist or OpenCV cannot load it.
  RaftFlow(const std::filesystem::path& onnx, std::pair<std::string, std::string> input_names);
  ~RaftFlow();
  RaftFlow(const RaftFlow&) = delete;
  RaftFlow& operator=(const RaftFlow&) = delete;

  Flow operator()(const io::ImageF& from, const io::ImageF& to);

 private:
  struct Net;
  std::unique_ptr<Net> net_;
  std::pair<std::string, std::string> inputs_;
  std::filesystem::path path_;
};

}  // namespace s4d::metrics
