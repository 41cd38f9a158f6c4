// report.md and report.csv from report.json: rows (method, scene), one column per metric key.
#include <algorithm>
#include <sstream>

#include "s4d/bench/frames_report.h"
#include "s4d/bench/metric_catalog.h"

namespace s4d::bench {

namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(4);
  s << std::fixed << v;
  return s.str();
}

}  // namespace

std::string report_table_markdown(const nlohmann::json& report) {
  std::ostringstream md;
  const auto& results = report.at("results");
  std::vector<std::string> styles;  // distinct, in order (a run's methods may use several)
  for (const auto& r : results)
    if (std::find(styles.begin(), styles.end(), r.at("style").get<std::string>()) == styles.end())
      styles.push_back(r.at("style").get<std::string>());
  for (size_t i = 0; i < styles.size(); ++i)
    md << (i == 0 ? "Style: `" : ", `") << styles[i] << (i + 1 == styles.size() ? "`.\n\n" : "`");
  md << "| method | scene |";
  // psnr is one value per run (the original scene's reconstruction): its header says so, and only
  // the original render's row shows it; the other rows' cells are "-" (kPsnrPerRun), never a copy.
  for (const auto& e : metric_catalog())
    md << " " << e.label << (e.key == "psnr" ? " (original scene, per run)" : "") << (e.higher_is_better ? " ↑" : " ↓") << " |";
  md << "\n|---|---|";
  for (size_t i = 0; i < metric_catalog().size(); ++i) md << "---|";
  md << "\n";
  std::vector<std::pair<std::string, std::string>> notes;  // key, why
  for (const auto& r : results) {
    md << "| " << r.at("method").get<std::string>() << " | " << r.at("scene").get<std::string>() << " |";
    for (const auto& e : metric_catalog()) {
      const auto& v = r.at(e.key);
      if (v.is_number()) {
        md << " " << number(v.get<double>()) << " |";
        continue;
      }
      const std::string why = v.at("unavailable").get<std::string>();
      md << (why == kPsnrPerRun ? " - |" : " n/a |");
      bool seen = false;
      for (const auto& n : notes) seen = seen || (n.first == e.key && n.second == why);
      if (!seen) notes.emplace_back(e.key, why);
    }
    md << "\n";
  }
  if (!notes.empty()) {
    const auto per_run = [](const auto& n) { return n.second == kPsnrPerRun; };
    const bool any_na = !std::all_of(notes.begin(), notes.end(), per_run), any_dash = std::any_of(notes.begin(), notes.end(), per_run);
    md << "\n";
    if (any_na) md << "n/a: not computed, never estimated.";
    if (any_dash) md << (any_na ? " " : "") << "-: a per-run value, shown on the original render's row only.";
    md << "\n\n";
    for (const auto& [key, why] : notes) md << "- `" << key << "`" << (why == kPsnrPerRun ? " (-)" : "") << ": " << why << "\n";
  }
  return md.str();
}

std::string report_markdown(const nlohmann::json& report) {
  std::ostringstream md;
  md << "# Style4D-Bench report\n\n" << report_table_markdown(report);
  md << "\n## Conventions\n\n";
  for (const auto& e : metric_catalog()) {
    const auto& i = report.at("metrics_info").at(e.key);
    md << "- `" << e.key << "` (" << i.at("direction").get<std::string>() << " is better): " << i.at("impl").get<std::string>()
       << "; " << i.at("convention").get<std::string>() << "\n";
  }
  md << (report.value("mode", "") == "merge" ? "\nPer-frame curves and sample frames: in each source report's folder.\n"
                                              : "\nPer-frame curves: `plots/`; sample frames: `contact_sheet.png`.\n");
  return md.str();
}

std::string report_csv(const nlohmann::json& report) {
  std::ostringstream csv;
  csv << "method,scene,style";
  for (const auto& e : metric_catalog()) csv << "," << e.key;
  csv << "\n";
  auto quoted = [](const std::string& s) {
    std::string q = "\"";
    for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return q + "\"";
  };
  for (const auto& r : report.at("results")) {
    csv << quoted(r.at("method").get<std::string>()) << "," << quoted(r.at("scene").get<std::string>()) << ","
        << quoted(r.at("style").get<std::string>());
    for (const auto& e : metric_catalog()) {
      const auto& v = r.at(e.key);
      csv << ",";
      if (v.is_number()) {
        std::ostringstream s;
        s.precision(10);
        s << v.get<double>();
        csv << s.str();
      }
    }
    csv << "\n";
  }
  return csv.str();
}

}  // namespace s4d::bench
