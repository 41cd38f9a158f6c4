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

// The psnr "unavailable" text of every row but the original render's: psnr scores the
// reconstruction of the original scene against the captured frames, one value per run (METRICS.md:
// "reconstruction (original scene)"), and a stylised render has no captured frames of its own.
// report.md shows these cells as "-" (frames_report_tables.cpp).
inline constexpr const char* kPsnrPerRun =
    "per run, not per style: psnr scores the original-scene render against the captured frames (the reconstruction) "
    "and is reported on the original render's row only; a stylised render has no captured frames to compare with "
    "(frames mode: add --frames set to the --original frames for that row)";

struct MethodResult {
  std::string name;
  std::filesystem::path frames;
  int frame_count = 0;
  std::map<std::string, double> means;                       // metric key -> value over the video
  std::map<std::string, std::vector<double>> per_frame;      // warp_loss: per scored pair (frame t, t+1)
  std::map<std::string, std::string> unavailable;            // keys this evaluation could not score, and why
  std::vector<int> sample_index;
  std::vector<io::ImageF> samples, original_samples;
};

// The frame indices kept for the contact sheet: `count` spread evenly over `frames` (first and last
// included).
std::vector<int> sample_indices(int frames, int count);

// psnr is scored only when `frames` is options.original itself (the same folder or file) and
// options.ground_truth is given; any other method's psnr is unavailable with kPsnrPerRun. A warp pair
// with every pixel occluded is left out of warp_loss's mean and its per_frame values; with none left,
// warp_loss is unavailable, saying why.
// Throws std::runtime_error naming the file when frames cannot be read, the videos differ in length
// or frame size, or a flow file is missing.
MethodResult evaluate_frames(const std::string& name, const std::filesystem::path& frames, const FramesOptions& options);

}  // namespace s4d::bench
