// Frames mode of `style4d bench`: score one method's stylised frames against the original-scene
// frames of the same cameras and times, with the weight-free metrics and, given their networks
// (native_learned.h), the native learned ones. Frames are read one at a time (a long video never
// sits in memory whole).
#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"
#include "s4d/metrics/uiqm.h"
#include "s4d/metrics/warp_loss.h"

namespace s4d::bench {

class NativeLearned;

enum class FlowSource { dis, raft, exact };
enum class FlowFrames { original, stylized };  // which frames the flow is computed on

struct FramesOptions {
  std::filesystem::path original;                   // the original-scene render of the same frames
  std::optional<std::filesystem::path> ground_truth;  // captured frames, for psnr of the original render
  metrics::UiqmVariant uiqm = metrics::UiqmVariant::a_funie;
  metrics::WarpNorm warp_norm = metrics::WarpNorm::abs;
  FlowSource flow = FlowSource::dis;
  FlowFrames flow_on = FlowFrames::original;
  std::filesystem::path raft_onnx;                         // FlowSource::raft
  std::pair<std::string, std::string> raft_inputs{"image1", "image2"};
  std::filesystem::path flow_dir;                          // FlowSource::exact: fw_NNNN.exr, bw_NNNN.exr
  int sample_frames = 4;                                   // frames kept for the contact sheet
  const NativeLearned* learned = nullptr;                  // the native learned metrics, when loaded
  std::vector<std::string> learned_keys;                   // the learned keys to score here (empty: all)
  std::filesystem::path style_image;                       // for style_lpips, style_loss_gram; empty: none
  std::map<std::string, std::string> bridged;              // keys the pyiqa bridge computed -> its impl text
};

struct MethodResult {
  std::string name;
  std::filesystem::path frames;
  int frame_count = 0;
  std::map<std::string, double> means;                       // metric key -> value over the video
  std::map<std::string, std::vector<double>> per_frame;      // warp_loss: per pair (frame t, t+1)
  std::map<std::string, std::string> unavailable;            // keys this evaluation could not score, and why
  std::vector<int> sample_index;
  std::vector<io::ImageF> samples, original_samples;
};

// The frame indices kept for the contact sheet: `count` spread evenly over `frames` (first and last
// included).
std::vector<int> sample_indices(int frames, int count);

// Throws std::runtime_error naming the file when frames cannot be read, the videos differ in length
// or frame size, or a flow file is missing.
MethodResult evaluate_frames(const std::string& name, const std::filesystem::path& frames, const FramesOptions& options);

}  // namespace s4d::bench
