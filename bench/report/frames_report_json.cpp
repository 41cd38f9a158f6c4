// report.json for the frames mode, and the convention text of the weight-free metrics as run.
#include <cmath>
#include <stdexcept>

#include "s4d/bench/frames_report.h"
#include "s4d/bench/metric_catalog.h"
#include "s4d/bench/native_learned.h"

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
                                                          : std::string("the renderer's exact flow (fw_NNNN.exr, bw_NNNN.exr)");
  return "flow t->t+1 and t+1->t: " + source + ", computed on the " +
         (o.flow_on == FlowFrames::original ? "original" : "stylised") +
         " frames; stylised t+1 warped to t (Resample2d, clamped bilinear); Lai 2018 forward-backward and "
         "motion-boundary occlusion mask; " +
         (o.warp_norm == metrics::WarpNorm::abs ? "mean |difference| (Style4D L1)" : "mean squared difference (Lai)") +
         " over unoccluded pixels and channels; mean over pairs, leaving out a pair occluded at every pixel (none "
         "left: unavailable)";
}

}  // namespace

nlohmann::json metric_values(const MethodResult& m) {
  nlohmann::json values = nlohmann::json::object();
  // A value when this evaluation scored the key; else its reason; else (a learned key nothing
  // computed) the catalog's note on what to supply.
  for (const auto& e : metric_catalog()) {
    if (auto it = m.unavailable.find(e.key); it != m.unavailable.end())
      values[e.key] = {{"unavailable", it->second}};
    else if (auto v = m.means.find(e.key); v != m.means.end())
      values[e.key] = v->second;
    else if (e.unavailable)
      values[e.key] = {{"unavailable", *e.unavailable}};
    else
      throw std::logic_error("metric_values: " + m.name + " has no value or reason for " + e.key);
  }
  return values;
}

nlohmann::json metrics_info(const FramesOptions& options) {
  nlohmann::json info = nlohmann::json::object();
  for (const auto& e : metric_catalog()) {
    const bool learned = options.learned != nullptr && options.learned->computes(e.key);
    if (auto b = options.bridged.find(e.key); b != options.bridged.end()) {
      info[e.key] = {{"impl", b->second},
                     {"convention", e.convention + "; mean over " + (e.key == "dists" || e.key == "dino_score" ? "pairs" : "frames")},
                     {"direction", e.higher_is_better ? "higher" : "lower"}};
      continue;
    }
    info[e.key] = {{"impl", learned ? options.learned->impl(e.key) : e.impl},
                   {"convention", learned ? options.learned->convention(e.key)
                                          : e.unavailable ? e.convention : native_convention(e.key, options)},
                   {"direction", e.higher_is_better ? "higher" : "lower"}};
  }
  return info;
}

nlohmann::json report_json(const std::vector<MethodResult>& methods, const ReportContext& c) {
  nlohmann::json results = nlohmann::json::array();
  for (const auto& m : methods) {
    nlohmann::json r = {{"method", m.name}, {"scene", c.scene}, {"style", c.style}, {"frames", m.frame_count},
                        {"inputs", {{"frames", m.frames.string()}, {"original", c.options.original.string()}}}};
    r.update(metric_values(m));
    r["per_frame"] = m.per_frame;
    results.push_back(std::move(r));
  }
  nlohmann::json inputs = {{"style_image", c.style_image.string()}, {"original", c.options.original.string()}};
  if (c.options.ground_truth) inputs["ground_truth"] = c.options.ground_truth->string();
  if (c.options.flow == FlowSource::exact) inputs["flow_dir"] = c.options.flow_dir.string();
  return {{"mode", "frames"}, {"inputs", inputs}, {"results", results}, {"metrics_info", metrics_info(c.options)}};
}

}  // namespace s4d::bench
