// The pyiqa bridge: the learned metrics without a native network, computed by a user-installed
// Python (pyiqa, torch) in a separate process over a file protocol (docs/bench.md, "Learned metrics",
// "The pyiqa bridge protocol"). `style4d bench --python PY` writes DIR/bridge/request.json (the
// metric keys and the PNG frame files of each sequence), runs `PY SCRIPT DIR/bridge/request.json`
// (SCRIPT: tools/pyiqa_bridge.py, embedded in the program, or --bridge-script FILE) with its output
// in DIR/bridge/bridge.log, and reads the response file the request names. Any failure (Python
// missing, non-zero exit, no or malformed response, an error for a metric, a wrong value count)
// makes the affected keys unavailable with the reason; nothing is ever estimated.
#pragma once
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "s4d/bench/frames_eval.h"

namespace s4d::bench {

inline constexpr const char* kBridgeProtocol = "s4d-pyiqa-bridge/1";

// The keys the bridge may compute, in METRICS.md's order: clipiqa_plus, musiq, qalign,
// musiq_paq2piq, dists, dino_score, ckdn.
const std::vector<std::string>& bridge_keys();
// Values the bridge returns for `key` over a sequence of `frames` frames: one per frame, or one per
// consecutive pair (dists, dino_score).
size_t bridge_value_count(const std::string& key, size_t frames);

struct BridgeSequence {
  std::string id;                            // unique within a request
  std::vector<std::filesystem::path> frames;  // PNG files in time order
  std::filesystem::path style_image;          // for ckdn; empty: none
  std::vector<std::string> metrics;           // bridge keys to compute on it
};

// Per sequence id and key: the values, or why there are none.
struct BridgeOutcome {
  std::map<std::string, std::map<std::string, std::vector<double>>> values;
  std::map<std::string, std::map<std::string, std::string>> errors;
  nlohmann::json versions = nlohmann::json::object();  // what the script reports of itself
};

nlohmann::json bridge_request(const std::vector<BridgeSequence>& sequences, const std::filesystem::path& output);
// Every requested (sequence, key) ends in `values` (a list of finite numbers of the expected count)
// or in `errors`.
BridgeOutcome parse_bridge_response(const nlohmann::json& response, const std::vector<BridgeSequence>& sequences);
BridgeOutcome bridge_failed(const std::vector<BridgeSequence>& sequences, const std::string& why);

struct BridgeOptions {
  std::filesystem::path python;                // --python
  std::optional<std::filesystem::path> script;  // --bridge-script; default: the embedded pyiqa_bridge.py
  std::filesystem::path work_dir;               // DIR/bridge
  std::vector<std::string> metrics;             // the keys to ask for (default: bridge_keys())
};

// The embedded tools/pyiqa_bridge.py.
const std::string& embedded_bridge_script();

// Runs the bridge once for all sequences. Throws only for local I/O errors (the work folder cannot be
// written); every failure of the Python side is reported in the outcome.
BridgeOutcome run_bridge(const BridgeOptions& options, const std::vector<BridgeSequence>& sequences);

// A sequence's frames as PNG files: a folder's PNGs in name order, or a video decoded into
// `decode_dir`.
std::vector<std::filesystem::path> frame_files(const std::filesystem::path& frames, const std::filesystem::path& decode_dir);

// One sequence's outcome into a result: per_frame values and their mean, or unavailable with the
// bridge's reason.
void apply_bridge(const BridgeOutcome& outcome, const std::string& id, const std::vector<std::string>& keys,
                  MethodResult& result);

// metrics_info's impl text of a bridged key: the interpreter and script, what the script reports of
// that key (pyiqa's metric, direction and score range) and of itself (versions).
std::string bridge_impl(const BridgeOptions& options, const BridgeOutcome& outcome, const std::string& key);

}  // namespace s4d::bench
