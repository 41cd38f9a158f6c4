// The run mode of `style4d bench`: a trained run's methods (the original scene and its styles)
// scored on both render protocols with the frames mode's evaluation, and the report built from them.
// Each metric is read from the protocol Style4D-Bench scores it on (METRICS.md's table):
// spatiotemporal consistency (warp_loss, dists) from the spiral video, everything else (imaging
// and aesthetic quality, content and subject consistency, psnr) from the fixed-view videos of the
// test cameras. Every weight-free score of both protocols is kept under each result's "protocols".
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "s4d/bench/frames_eval.h"

namespace s4d::bench {

enum class Protocol { test, spiral };

const char* protocol_name(Protocol protocol);  // "test", "spiral"
Protocol metric_protocol(const std::string& key);

// Several sequences of one method as one result: per-frame values appended in order (means are
// frame-weighted; warp pairs never span two sequences), unavailable reasons and contact-sheet
// samples from the first sequence. Throws std::invalid_argument for no sequences.
MethodResult pool_sequences(const std::string& name, const std::vector<MethodResult>& sequences);

struct RunMethodResult {
  MethodResult test;                  // pooled over the test cameras' sequences
  MethodResult spiral;
  std::string style;                  // the style image's stem; "none" for the original scene
  std::filesystem::path style_image;  // empty for the original scene
};

struct RunReportContext {
  std::string scene;
  std::filesystem::path run, renders;  // RUN; DIR/renders
  int spiral_frames = 0;
  FramesOptions options;  // as the spiral was scored (the warp loss's flow is described from it)
};

// Each metric from its protocol (metric_protocol); name, samples and the other fields from `test`.
MethodResult headline(const RunMethodResult& method);

// report_json's layout ("results", "metrics_info", "inputs"; "mode": "run") plus, per result,
// "protocols": {"test": {frames, keys...}, "spiral": {...}}.
nlohmann::json run_report_json(const std::vector<RunMethodResult>& methods, const RunReportContext& context);

// report.json, report.md, report.csv, plots/ and contact_sheet.png (fixed-view samples) under `out`.
void write_run_report(const std::filesystem::path& out, const std::vector<RunMethodResult>& methods,
                      const RunReportContext& context);

}  // namespace s4d::bench
