// The bridge's request and response (pyiqa_bridge.h); the process and frame files are in
// bridge_process.cpp.
#include "s4d/bench/pyiqa_bridge.h"

#include <algorithm>
#include <cmath>

namespace s4d::bench {

const std::vector<std::string>& bridge_keys() {
  static const std::vector<std::string> keys = {"clipiqa_plus", "musiq", "qalign", "musiq_paq2piq", "dists", "dino_score", "ckdn"};
  return keys;
}

size_t bridge_value_count(const std::string& key, size_t frames) {
  if (key == "dists" || key == "dino_score") return frames < 2 ? 0 : frames - 1;
  return frames;
}

nlohmann::json bridge_request(const std::vector<BridgeSequence>& sequences, const std::filesystem::path& output) {
  nlohmann::json seqs = nlohmann::json::array();
  std::vector<std::string> all;
  for (const BridgeSequence& s : sequences) {
    nlohmann::json frames = nlohmann::json::array();
    for (const auto& f : s.frames) frames.push_back(f.string());
    seqs.push_back({{"id", s.id}, {"frames", frames}, {"style_image", s.style_image.string()}, {"metrics", s.metrics}});
    for (const std::string& k : s.metrics)
      if (std::find(all.begin(), all.end(), k) == all.end()) all.push_back(k);
  }
  return {{"protocol", kBridgeProtocol}, {"metrics", all}, {"sequences", seqs}, {"output", output.string()}};
}

BridgeOutcome bridge_failed(const std::vector<BridgeSequence>& sequences, const std::string& why) {
  BridgeOutcome o;
  for (const BridgeSequence& s : sequences)
    for (const std::string& k : s.metrics) o.errors[s.id][k] = why;
  return o;
}

namespace {

// The reason a response's entry for (sequence, key) is unusable, or nullopt with `values` filled.
std::optional<std::string> read_values(const nlohmann::json& response, const BridgeSequence& s, const std::string& key,
                                       std::vector<double>& values) {
  const auto& errors = response.contains("errors") ? response["errors"] : nlohmann::json::object();
  if (errors.is_object() && errors.contains(key))
    return errors[key].is_string() ? errors[key].get<std::string>() : errors[key].dump();
  const auto& results = response.contains("results") ? response["results"] : nlohmann::json::object();
  if (!results.is_object() || !results.contains(s.id) || !results[s.id].is_object() || !results[s.id].contains(key))
    return "the response has no results." + s.id + "." + key;
  const auto& v = results[s.id][key];
  if (v.is_object() && v.contains("error"))
    return v["error"].is_string() ? v["error"].get<std::string>() : v["error"].dump();
  if (!v.is_array()) return "results." + s.id + "." + key + " is not a list of numbers";
  for (const auto& e : v) {
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      return "results." + s.id + "." + key + " holds " + e.dump() + ", not a finite number";
    values.push_back(e.get<double>());
  }
  const size_t expected = bridge_value_count(key, s.frames.size());
  if (values.size() != expected)
    return "results." + s.id + "." + key + " holds " + std::to_string(values.size()) + " values for " +
           std::to_string(s.frames.size()) + " frames, expected " + std::to_string(expected);
  return std::nullopt;
}

}  // namespace

BridgeOutcome parse_bridge_response(const nlohmann::json& response, const std::vector<BridgeSequence>& sequences) {
  if (!response.is_object() || response.value("protocol", std::string()) != kBridgeProtocol)
    return bridge_failed(sequences, std::string("the response is not a JSON object with \"protocol\": \"") + kBridgeProtocol + "\"");
  BridgeOutcome o;
  if (response.contains("versions") && response["versions"].is_object()) o.versions = response["versions"];
  for (const BridgeSequence& s : sequences)
    for (const std::string& k : s.metrics) {
      std::vector<double> values;
      if (auto why = read_values(response, s, k, values))
        o.errors[s.id][k] = *why;
      else
        o.values[s.id][k] = std::move(values);
    }
  return o;
}

void apply_bridge(const BridgeOutcome& outcome, const std::string& id, const std::vector<std::string>& keys,
                  MethodResult& result) {
  for (const std::string& k : keys) {
    if (auto e = outcome.errors.find(id); e != outcome.errors.end() && e->second.count(k) != 0) {
      result.unavailable[k] = "pyiqa bridge: " + e->second.at(k);
      continue;
    }
    const auto s = outcome.values.find(id);
    if (s == outcome.values.end() || s->second.count(k) == 0) continue;  // not asked for this sequence
    const std::vector<double>& v = s->second.at(k);
    if (v.empty()) {
      result.unavailable[k] = "needs at least 2 frames";
      continue;
    }
    double sum = 0;
    for (double x : v) sum += x;
    result.per_frame[k] = v;
    result.means[k] = sum / double(v.size());
    result.unavailable.erase(k);
  }
}

std::string bridge_impl(const BridgeOptions& options, const BridgeOutcome& outcome, const std::string& key) {
  std::string text = "pyiqa bridge: " + options.python.string() + " " +
                     (options.script ? options.script->string() : std::string("pyiqa_bridge.py (embedded)"));
  const nlohmann::json& v = outcome.versions;
  if (v.contains(key) && v[key].is_string()) text += ", " + v[key].get<std::string>();
  nlohmann::json shared = nlohmann::json::object();  // the script's own versions, not another key's
  for (const auto& [name, value] : v.items())
    if (std::find(bridge_keys().begin(), bridge_keys().end(), name) == bridge_keys().end()) shared[name] = value;
  if (!shared.empty()) text += " " + shared.dump();
  return text;
}

}  // namespace s4d::bench
