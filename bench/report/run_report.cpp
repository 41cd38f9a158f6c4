#include "s4d/bench/run_report.h"

#include <stdexcept>

#include "s4d/bench/frames_report.h"
#include "s4d/bench/metric_catalog.h"
#include "s4d/util/atomic_file.h"

namespace s4d::bench {

const char* protocol_name(Protocol p) { return p == Protocol::test ? "test" : "spiral"; }

Protocol metric_protocol(const std::string& key) {
  return key == "warp_loss" || key == "dists" ? Protocol::spiral : Protocol::test;
}

MethodResult pool_sequences(const std::string& name, const std::vector<MethodResult>& sequences) {
  if (sequences.empty()) throw std::invalid_argument("pool_sequences: no sequences for " + name);
  MethodResult out = sequences.front();
  out.name = name;
  for (size_t s = 1; s < sequences.size(); ++s) {
    out.frame_count += sequences[s].frame_count;
    for (const auto& [key, values] : sequences[s].per_frame) {
      std::vector<double>& all = out.per_frame[key];
      all.insert(all.end(), values.begin(), values.end());
    }
  }
  out.means.clear();
  for (const auto& [key, values] : out.per_frame) {
    double sum = 0;
    for (double v : values) sum += v;
    if (!values.empty()) out.means[key] = sum / double(values.size());
  }
  // A key with values from some sequence only (warp_loss of a 1-frame camera) is scored on those; a
  // key no sequence scored keeps the first reason any sequence gave.
  for (size_t s = 1; s < sequences.size(); ++s)
    for (const auto& [key, why] : sequences[s].unavailable) out.unavailable.emplace(key, why);
  for (const auto& [key, mean] : out.means) out.unavailable.erase(key);
  return out;
}

MethodResult headline(const RunMethodResult& m) {
  MethodResult out = m.test;
  out.means.clear();
  out.per_frame.clear();
  out.unavailable.clear();
  for (const auto& e : metric_catalog()) {
    const MethodResult& from = metric_protocol(e.key) == Protocol::test ? m.test : m.spiral;
    if (auto it = from.means.find(e.key); it != from.means.end()) out.means[e.key] = it->second;
    if (auto it = from.per_frame.find(e.key); it != from.per_frame.end()) out.per_frame[e.key] = it->second;
    if (auto it = from.unavailable.find(e.key); it != from.unavailable.end()) out.unavailable[e.key] = it->second;
  }
  return out;
}

namespace {

nlohmann::json protocol_scores(const MethodResult& r) {
  nlohmann::json scores = {{"frames", r.frame_count}, {"frames_dir", r.frames.string()}};
  const nlohmann::json values = metric_values(r);
  for (const auto& e : metric_catalog())
    // Learned keys nothing computed say the same in both protocols; they are left out here.
    if (!e.unavailable || r.means.count(e.key) != 0 || r.unavailable.count(e.key) != 0) scores[e.key] = values.at(e.key);
  return scores;
}

}  // namespace

nlohmann::json run_report_json(const std::vector<RunMethodResult>& methods, const RunReportContext& c) {
  nlohmann::json info = metrics_info(c.options);
  for (auto it = info.begin(); it != info.end(); ++it) {
    nlohmann::json& entry = it.value();
    const Protocol p = metric_protocol(it.key());
    entry["protocol"] = protocol_name(p);
    entry["convention"] = entry["convention"].get<std::string>() +
                          (p == Protocol::test ? "; run mode: fixed-view videos of the test cameras, frames of all cameras pooled"
                                               : "; run mode: the spiral video (" + std::to_string(c.spiral_frames) + " frames)");
  }
  nlohmann::json results = nlohmann::json::array();
  for (const RunMethodResult& m : methods) {
    const MethodResult h = headline(m);
    nlohmann::json r = {{"method", h.name},
                        {"scene", c.scene},
                        {"style", m.style},
                        {"frames", m.test.frame_count + m.spiral.frame_count},
                        {"inputs", {{"test", m.test.frames.string()}, {"spiral", m.spiral.frames.string()}}}};
    if (!m.style_image.empty()) r["inputs"]["style_image"] = m.style_image.string();
    r.update(metric_values(h));
    r["per_frame"] = h.per_frame;
    r["protocols"] = {{"test", protocol_scores(m.test)}, {"spiral", protocol_scores(m.spiral)}};
    results.push_back(std::move(r));
  }
  nlohmann::json inputs = {{"run", c.run.string()}, {"renders", c.renders.string()}, {"spiral_frames", c.spiral_frames}};
  if (c.options.ground_truth) inputs["ground_truth"] = c.options.ground_truth->string();
  return {{"mode", "run"}, {"inputs", inputs}, {"results", results}, {"metrics_info", info}};
}

void write_run_report(const std::filesystem::path& out, const std::vector<RunMethodResult>& methods, const RunReportContext& c) {
  std::vector<MethodResult> headlines;
  for (const RunMethodResult& m : methods) headlines.push_back(headline(m));
  write_report_files(out, run_report_json(methods, c), headlines);
}

}  // namespace s4d::bench
