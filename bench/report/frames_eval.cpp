#include "s4d/bench/frames_eval.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "s4d/bench/native_learned.h"
#include "s4d/data/frame_reader.h"
#include "s4d/metrics/flow.h"
#include "s4d/io/psnr.h"
#include "s4d/metrics/ssim.h"

namespace s4d::bench {

namespace {

std::filesystem::path flow_file(const std::filesystem::path& dir, const char* prefix, int pair) {
  char name[32];
  std::snprintf(name, sizeof name, "%s_%04d.exr", prefix, pair);
  return dir / name;
}

// Forward (t -> t+1) and backward flow of one pair from the chosen source.
class PairFlow {
 public:
  explicit PairFlow(const FramesOptions& o) : o_(o) {
    if (o.flow == FlowSource::raft) raft_ = std::make_unique<metrics::RaftFlow>(o.raft_onnx, o.raft_inputs);
  }
  std::pair<metrics::Flow, metrics::Flow> operator()(const io::ImageF& a, const io::ImageF& b, int pair) {
    switch (o_.flow) {
      case FlowSource::dis: return {metrics::dis_flow(a, b), metrics::dis_flow(b, a)};
      case FlowSource::raft: return {(*raft_)(a, b), (*raft_)(b, a)};
      case FlowSource::exact: break;
    }
    return {metrics::read_flow_exr(flow_file(o_.flow_dir, "fw", pair)), metrics::read_flow_exr(flow_file(o_.flow_dir, "bw", pair))};
  }

 private:
  const FramesOptions& o_;
  std::unique_ptr<metrics::RaftFlow> raft_;
};

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / double(v.size());
}

// Whether `frames` is the original render itself (the same folder or video file), the one row whose
// psnr is the reconstruction's.
bool is_original(const std::filesystem::path& frames, const std::filesystem::path& original) {
  std::error_code ec;
  return std::filesystem::equivalent(frames, original, ec) && !ec;
}

std::string flow_name(const FramesOptions& o) {
  switch (o.flow) {
    case FlowSource::dis: return "DIS";
    case FlowSource::raft: return "RAFT";
    case FlowSource::exact: break;
  }
  return "exact (--flow-dir " + o.flow_dir.string() + ")";
}

}  // namespace

std::vector<int> sample_indices(int frames, int count) {
  std::vector<int> out;
  const int n = std::min(frames, count);
  for (int i = 0; i < n; ++i) out.push_back(n == 1 ? 0 : int(int64_t(frames - 1) * i / (n - 1)));
  return out;
}

MethodResult evaluate_frames(const std::string& name, const std::filesystem::path& frames, const FramesOptions& o) {
  data::FrameReader styl(frames), orig(o.original);
  if (styl.size() != orig.size())
    throw std::runtime_error(frames.string() + ": has " + std::to_string(styl.size()) + " frames but the original " +
                             o.original.string() + " has " + std::to_string(orig.size()));
  std::unique_ptr<data::FrameReader> truth;
  if (o.ground_truth) {
    truth = std::make_unique<data::FrameReader>(*o.ground_truth);
    if (truth->size() != orig.size())
      throw std::runtime_error(o.ground_truth->string() + ": has " + std::to_string(truth->size()) +
                               " frames but the original has " + std::to_string(orig.size()));
  }
  MethodResult r{name, frames, styl.size(), {}, {}, {}, sample_indices(styl.size(), o.sample_frames), {}, {}};
  const bool scores_psnr = truth && is_original(frames, o.original);
  int occluded_pairs = 0;  // pairs with no unoccluded pixel: left out of the warp loss
  PairFlow flow(o);
  io::ImageF prev_s, prev_o;
  for (int i = 0; i < styl.size(); ++i) {
    io::ImageF s = styl.next_counted(), g = orig.next_counted();
    if (s.width != g.width || s.height != g.height)
      throw std::runtime_error(frames.string() + ": frame " + std::to_string(i) + " is " + std::to_string(s.width) + "x" +
                               std::to_string(s.height) + " but the original's is " + std::to_string(g.width) + "x" +
                               std::to_string(g.height));
    r.per_frame["content_ssim"].push_back(metrics::ssim(s, g));
    r.per_frame["uiqm"].push_back(metrics::uiqm(s, o.uiqm));
    if (truth) {
      const io::ImageF captured = truth->next_counted();
      if (scores_psnr) r.per_frame["psnr"].push_back(io::psnr(g, captured));
    }
    if (o.learned) o.learned->score_frame(s, g, o.style_image, i > 0, o.learned_keys, r.per_frame);
    if (i > 0) {
      const bool on_orig = o.flow_on == FlowFrames::original;
      const auto [fw, bw] = flow(on_orig ? prev_o : prev_s, on_orig ? g : s, i - 1);
      const metrics::PairWarpError pair = metrics::warp_error(prev_s, s, fw, bw, o.warp_norm);
      if (pair.scored())
        r.per_frame["warp_loss"].push_back(pair.error);
      else
        ++occluded_pairs;
    }
    if (std::find(r.sample_index.begin(), r.sample_index.end(), i) != r.sample_index.end()) {
      r.samples.push_back(s);
      r.original_samples.push_back(g);
    }
    prev_s = std::move(s);
    prev_o = std::move(g);
  }
  for (const auto& [key, values] : r.per_frame)
    if (!values.empty()) r.means[key] = mean_of(values);
  if (!is_original(frames, o.original))
    r.unavailable["psnr"] = kPsnrPerRun;
  else if (!truth)
    r.unavailable["psnr"] = "needs the captured frames: pass --ground-truth DIR (frames of the same cameras and times as --original) "
                            "to score the original-scene render";
  if (styl.size() < 2)
    r.unavailable["warp_loss"] = "needs at least 2 frames";
  else if (r.means.count("warp_loss") == 0)
    r.unavailable["warp_loss"] = "every one of the " + std::to_string(occluded_pairs) +
                                 " frame pairs is occluded at every pixel under the " + flow_name(o) +
                                 " flow (forward-backward or motion-boundary check), so no pixel could be compared: check "
                                 "the flow (--flow, --flow-dir) and that consecutive frames show the same scene";
  if (o.learned) {
    const auto scored_here = [&](const std::string& key) {
      return o.learned_keys.empty() || std::find(o.learned_keys.begin(), o.learned_keys.end(), key) != o.learned_keys.end();
    };
    for (const auto& [key, why] : o.learned->unavailable())
      if (scored_here(key)) r.unavailable[key] = why;
    for (const char* key : {"dists", "dino_score"})
      if (styl.size() < 2 && o.learned->computes(key) && scored_here(key)) r.unavailable[key] = "needs at least 2 frames";
    if (o.style_image.empty())
      for (const char* key : {"style_lpips", "style_loss_gram", "ckdn"})
        if (o.learned->computes(key) && scored_here(key))
          r.unavailable[key] = "no style image: this method is the unstylised original scene";
  }
  return r;
}

}  // namespace s4d::bench
