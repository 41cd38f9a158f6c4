// Writes the frames-mode report's files.
#include <map>

#include "s4d/bench/contact_sheet.h"
#include "s4d/bench/frames_report.h"
#include "s4d/bench/line_plot.h"
#include "s4d/bench/metric_catalog.h"
#include "s4d/bench/report_html.h"
#include "s4d/util/atomic_file.h"

namespace s4d::bench {

void write_frames_report(const std::filesystem::path& out, const std::vector<MethodResult>& methods, const ReportContext& c) {
  write_report_files(out, report_json(methods, c), methods);
}

void write_report_files(const std::filesystem::path& out, const nlohmann::json& report, const std::vector<MethodResult>& methods) {
  std::filesystem::create_directories(out / "plots");
  util::write_file_atomic(out / "report.json", report.dump(2) + "\n");
  util::write_file_atomic(out / "report.md", report_markdown(report));
  util::write_file_atomic(out / "report.csv", report_csv(report));

  std::map<std::string, std::vector<Series>> curves;  // metric key -> one series per method
  for (const auto& m : methods)
    for (const auto& [key, values] : m.per_frame)
      if (!values.empty()) curves[key].push_back({m.name, values});
  for (const auto& [key, series] : curves) {
    const MetricEntry& e = metric_entry(key);
    const std::string x = key == "warp_loss" ? "frame pair (t, t+1)" : "frame";
    io::write_png(out / "plots" / (key + ".png"),
                  line_plot(e.label + " per " + x + " (" + (e.higher_is_better ? "higher" : "lower") + " is better)", x, key, series));
  }

  if (!methods.empty() && !methods[0].samples.empty()) {
    std::vector<SheetRow> rows = {{"original", methods[0].original_samples}};
    for (const auto& m : methods)
      if (m.name != "original") rows.push_back({m.name, m.samples});  // a method scoring the original is that row
    io::write_png(out / "contact_sheet.png", contact_sheet(rows, methods[0].sample_index));
  }
  write_report_html(out, report);
}

}  // namespace s4d::bench
