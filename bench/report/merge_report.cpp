#include "s4d/bench/merge_report.h"
#include "s4d/bench/report_html.h"

#include <fstream>
#include <stdexcept>

#include "s4d/bench/frames_report.h"
#include "s4d/bench/metric_catalog.h"
#include "s4d/util/atomic_file.h"

namespace s4d::bench {

namespace {

nlohmann::json read_report(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read (expected a report.json written by style4d bench)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("results") || !j["results"].is_array() || !j.contains("metrics_info") ||
      !j["metrics_info"].is_object())
    throw std::runtime_error(file.string() + ": not a style4d bench report (no 'results' array or 'metrics_info' object)");
  return j;
}

}  // namespace

nlohmann::json merge_reports(const std::vector<std::filesystem::path>& inputs) {
  if (inputs.empty()) throw std::invalid_argument("merge_reports: no reports given");
  nlohmann::json results = nlohmann::json::array(), sources = nlohmann::json::array(), info;
  std::filesystem::path first;
  for (const std::filesystem::path& input : inputs) {
    const std::filesystem::path file = std::filesystem::is_directory(input) ? input / "report.json" : input;
    const nlohmann::json report = read_report(file);
    if (info.is_null()) {
      info = report["metrics_info"];
      first = file;
    }
    for (const auto& e : metric_catalog())
      for (const char* field : {"impl", "convention", "direction"}) {
        const nlohmann::json mine = report["metrics_info"].value(e.key, nlohmann::json::object()).value(field, nlohmann::json());
        const nlohmann::json theirs = info.value(e.key, nlohmann::json::object()).value(field, nlohmann::json());
        if (mine != theirs)
          throw std::runtime_error(file.string() + ": metrics_info." + e.key + "." + field + " is " + mine.dump() + " but " +
                                   first.string() + " has " + theirs.dump() +
                                   "; scores measured differently cannot share a column (re-run with the same options)");
      }
    for (nlohmann::json r : report["results"]) {
      for (const auto& other : results)
        if (other.at("method") == r.at("method") && other.at("scene") == r.at("scene") && other.at("style") == r.at("style"))
          throw std::runtime_error(file.string() + ": method " + r.at("method").dump() + ", scene " + r.at("scene").dump() +
                                   ", style " + r.at("style").dump() + " is already in " + other.at("source").get<std::string>());
      r["source"] = file.string();
      results.push_back(std::move(r));
    }
    sources.push_back(file.string());
  }
  return {{"mode", "merge"}, {"inputs", {{"reports", sources}}}, {"results", results}, {"metrics_info", info}};
}

void write_merged_report(const std::filesystem::path& out, const nlohmann::json& merged) {
  std::filesystem::create_directories(out);
  util::write_file_atomic(out / "report.json", merged.dump(2) + "\n");
  util::write_file_atomic(out / "report.md", report_markdown(merged));
  util::write_file_atomic(out / "report.csv", report_csv(merged));
  write_report_html(out, merged);
}

}  // namespace s4d::bench
