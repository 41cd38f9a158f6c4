// The frames-mode report: report.json (METRICS.md's key contract: every key a number or
// {"unavailable": why}, plus metrics_info), report.md (methods x scenes x metrics, the paper's
// layout), report.csv, per-frame curves (plots/<key>.png) and a contact sheet (contact_sheet.png).
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "s4d/bench/frames_eval.h"

namespace s4d::bench {

struct ReportContext {
  std::string scene, style;
  std::filesystem::path style_image;
  FramesOptions options;
};

nlohmann::json report_json(const std::vector<MethodResult>& methods, const ReportContext& context);

// The parts of report_json that the run mode (run_report.h) shares: one result's metric keys, each
// a number or {"unavailable": why}; and metrics_info, the weight-free conventions as `options` run.
nlohmann::json metric_values(const MethodResult& method);
nlohmann::json metrics_info(const FramesOptions& options);

// Both read a report_json() value: rows (method, scene), one column per metric key.
std::string report_markdown(const nlohmann::json& report);
// The metrics table of report.md with its n/a notes, for reports that embed it (the demo's).
std::string report_table_markdown(const nlohmann::json& report);
std::string report_csv(const nlohmann::json& report);

// Writes every file under `out` (created if needed; JSON, Markdown and CSV atomically).
void write_frames_report(const std::filesystem::path& out, const std::vector<MethodResult>& methods,
                         const ReportContext& context);

// The same files from an already built report (`report` in report_json's layout): the plots draw
// `methods`' per-frame values, the contact sheet their samples.
void write_report_files(const std::filesystem::path& out, const nlohmann::json& report, const std::vector<MethodResult>& methods);

}  // namespace s4d::bench
