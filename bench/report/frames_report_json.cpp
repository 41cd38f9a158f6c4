// report.json for the frames mode, and the convention text of the weight-free metrics as run.
#include <cmath>

#include "s4d/bench/frames_report.h"
#include "s4d/bench/metric_catalog.h"

namespace s4d::bench {

namespace {

std::string native_convention(const std::string& key, const FramesOptions& o) {
  if (key == "uiqm")
    return o.uiqm == metrics::UiqmVariant::a_funie
               ? "variant A (FUnIE-GAN uqim_utils.py, Python-3 port): 8-bit levels, no resize, 10x10 blocks, "
                 "lambda_B 0.144 as published; mean over frames"
               : "variant B (xueleichen nevaluate.py, scikit-image < 0.18): uint8 arithmetic, 8x8 blocks, PLIP logAMEE; "
                 "mean over frames";
  if (key == "content_ssim")
    return "3DGS ssim: stylised vs original frame, RGB [0,1], 11x11 Gaussian sigma 1.5, zero padding, mean over all "
           "pixels and channels; mean over frames";
  if (key == "psnr")
    return "original-scene render vs --ground-truth: RGB [0,1], MSE over pixels and channels, 10 log10(1/MSE), "
           "100 dB for identical frames; mean over frames";
  // warp_loss
  const std::string source = o.flow == FlowSource::dis    ? "OpenCV DIS PRESET_MEDIUM on 8-bit gray"
                             : o.flow == FlowSource::raft ? "RAFT ONNX " + o.raft_onnx.string()
                                                          : "exact flow from " + o.flow_dir.string();
  return "flow t->t+1 and t+1->t: " + source + ", computed on the " +
         (o.flow_on == FlowFrames::original ? "original" : "stylised") +
         " frames; stylised t+1 warped to t (Resample2d, clamped bilinear); Lai 2018 forward-backward and "
         "motion-boundary occlusion mask; " +
         (o.warp_norm == metrics::WarpNorm::abs ? "mean |difference| (Style4D L1)" : "mean squared difference (Lai)") +
         " over unoccluded pixels and channels; mean over pairs";
}

nlohmann::json value_or_unavailable(const MethodResult& m, const MetricEntry& e) {
  if (e.unavailable) return {{"unavailable", *e.unavailable}};
  if (auto it = m.unavailable.find(e.key); it != m.unavailable.end()) return {{"unavailable", it->second}};
  return m.means.at(e.key);
}

}  // namespace

nlohmann::json report_json(const std::vector<MethodResult>& methods, const ReportContext& c) {
  nlohmann::json info = nlohmann::json::object();
  for (const auto& e : metric_catalog())
    info[e.key] = {{"impl", e.impl},
                   {"convention", e.unavailable ? e.convention : native_convention(e.key, c.options)},
                   {"direction", e.higher_is_better ? "higher" : "lower"}};
  nlohmann::json results = nlohmann::json::array();
  for (const auto& m : methods) {
    nlohmann::json r = {{"method", m.name}, {"scene", c.scene}, {"style", c.style}, {"frames", m.frame_count},
                        {"inputs", {{"frames", m.frames.string()}, {"original", c.options.original.string()}}}};
    for (const auto& e : metric_catalog()) r[e.key] = value_or_unavailable(m, e);
    r["per_frame"] = m.per_frame;
    results.push_back(std::move(r));
  }
  nlohmann::json inputs = {{"style_image", c.style_image.string()}, {"original", c.options.original.string()}};
  if (c.options.ground_truth) inputs["ground_truth"] = c.options.ground_truth->string();
  return {{"mode", "frames"}, {"inputs", inputs}, {"results", results}, {"metrics_info", info}};
}

}  // namespace s4d::bench
