// The merge step of a benchmark sweep (ARCHITECTURE.md "Scale beyond one machine"): each job of a
// sweep (scenes x styles x methods) writes its own report.json with `style4d bench`; merging puts
// their results into one table, the paper's methods x scenes layout.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

namespace s4d::bench {

// `inputs`: report folders (their report.json) or report.json files. The merged report has
// report_json's layout with "mode": "merge", every result tagged with its "source" file, and
// "inputs": {"reports": [...]}. Throws std::runtime_error naming the file: unreadable or not a
// report (no 'results' array or 'metrics_info'); a metric measured differently from the first
// report (impl, convention or direction differ: the numbers would not share a column); a
// (method, scene, style) row another report already has. std::invalid_argument for fewer than 1 input.
nlohmann::json merge_reports(const std::vector<std::filesystem::path>& inputs);

// report.json, report.md and report.csv of a merged report under `out` (created if needed).
void write_merged_report(const std::filesystem::path& out, const nlohmann::json& merged);

}  // namespace s4d::bench
