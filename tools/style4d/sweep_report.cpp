// style4d sweep report: every finished bench cell's report.json merged (bench::merge_reports) into
// the paper-style table: rows scene x method (means over the styles), the 12 Style4D-Bench metric
// columns, the best per scene in bold; report.csv/report.json with every key, results.csv with one
// row per cell, a grouped bar plot per metric, and the cells that are missing.
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>
#include <sstream>

#include "s4d/bench/merge_report.h"
#include "s4d/bench/metric_catalog.h"
#include "s4d/io/image_io.h"
#include "s4d/util/atomic_file.h"
#include "sweep.h"

namespace s4d::cli::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The paper's table: METRICS.md's 12 Style4D-Bench metrics (the Gram loss and PSNR are extra keys).
bool in_table(const std::string& key) { return key != "style_loss_gram" && key != "psnr"; }

std::string fixed(double v) {
  std::ostringstream s;
  s.precision(4);
  s << std::fixed << v;
  return s.str();
}

std::string exact(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

// One grouped bar chart: a group per scene, a bar per method; NaN bars are left out.
void bar_plot(const fs::path& file, const std::string& title, const std::vector<std::string>& groups,
              const std::vector<std::string>& series, const std::vector<std::vector<double>>& values) {
  const int W = 800, H = 450, left = 70, right = 150, top = 40, bottom = 50;
  double lo = 0, hi = 0;
  for (const auto& row : values)
    for (double v : row)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (hi - lo < 1e-12) hi = lo + 1;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar black(0, 0, 0), grid(225, 225, 225);
  const cv::Scalar colours[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44}, {214, 39, 40}, {148, 103, 189}, {140, 86, 75}};
  const int x0 = left, x1 = W - right, y0 = H - bottom, y1 = top;
  auto py = [&](double v) { return y0 - int(std::lround((v - lo) / (hi - lo) * (y0 - y1))); };
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  for (int t = 0; t <= 5; ++t) {
    const double v = lo + (hi - lo) * t / 5;
    cv::line(img, {x0, py(v)}, {x1, py(v)}, grid, 1);
    cv::putText(img, fixed(v), {4, py(v) + 4}, font, 0.4, black, 1, cv::LINE_AA);
  }
  const int group_w = (x1 - x0) / std::max<int>(1, static_cast<int>(groups.size()));
  const int bar_w = std::max(2, (group_w - 20) / std::max<int>(1, static_cast<int>(series.size())));
  for (size_t g = 0; g < groups.size(); ++g) {
    const int gx = x0 + static_cast<int>(g) * group_w + 10;
    for (size_t s = 0; s < series.size(); ++s) {
      const double v = values[s][g];
      if (!std::isfinite(v)) continue;
      const int bx = gx + static_cast<int>(s) * bar_w;
      cv::rectangle(img, cv::Point(bx, std::min(py(v), py(0))), cv::Point(bx + bar_w - 2, std::max(py(v), py(0))), colours[s % 6], cv::FILLED);
    }
    cv::putText(img, groups[g], {gx, y0 + 20}, font, 0.45, black, 1, cv::LINE_AA);
  }
  cv::line(img, {x0, py(0)}, {x1, py(0)}, black, 1);
  cv::line(img, {x0, y0}, {x0, y1}, black, 1);
  cv::putText(img, title, {x0, 24}, font, 0.6, black, 1, cv::LINE_AA);
  for (size_t s = 0; s < series.size(); ++s) {
    const int ly = y1 + 20 * static_cast<int>(s) + 10;
    cv::rectangle(img, cv::Point(x1 + 15, ly - 6), cv::Point(x1 + 35, ly + 6), colours[s % 6], cv::FILLED);
    cv::putText(img, series[s], {x1 + 42, ly + 4}, font, 0.45, black, 1, cv::LINE_AA);
  }
  io::ImageF out{W, H, 3, std::vector<float>(size_t(W) * H * 3)};
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c) out.data[(size_t(y) * W + x) * 3 + c] = img.at<cv::Vec3b>(y, x)[c] / 255.0f;
  io::write_png(file, out);
}

}  // namespace

int write_report(const Manifest& m, const fs::path& out) {
  std::vector<std::string> scenes, methods;  // in manifest order; a scene label names its preset when there are several
  std::set<std::string> presets;
  for (const Cell* c : m.stage_cells("bench")) presets.insert(c->preset);
  auto scene_label = [&](const Cell& c) { return presets.size() > 1 ? c.scene + " (" + c.preset + ")" : c.scene; };
  std::vector<fs::path> reports;
  std::vector<const Cell*> finished, missing;
  for (const Cell* c : m.stage_cells("bench")) {
    if (std::find(scenes.begin(), scenes.end(), scene_label(*c)) == scenes.end()) scenes.push_back(scene_label(*c));
    if (std::find(methods.begin(), methods.end(), c->method) == methods.end()) methods.push_back(c->method);
    if (cell_done(m, *c)) {
      finished.push_back(c);
      reports.push_back(c->outputs.at(0));
    } else {
      missing.push_back(c);
    }
  }
  // One result per bench cell, labelled from the manifest (the run names its style "STYLE.METHOD").
  json results = json::array(), info = json::object();
  if (!reports.empty()) {
    const json merged = bench::merge_reports(reports);
    info = merged.at("metrics_info");
    for (size_t i = 0; i < finished.size(); ++i) {
      const json& r = merged.at("results").at(i);
      json row = {{"cell", finished[i]->id}, {"scene", scene_label(*finished[i])}, {"method", finished[i]->method},
                  {"style", finished[i]->style}};
      for (const auto& e : bench::metric_catalog()) row[e.key] = r.at(e.key);
      results.push_back(row);
    }
  }
  // Rows: scene x method, each metric the mean over the styles that finished.
  json rows = json::array();
  const size_t styles_expected = m.stage_cells("bench").size() / std::max<size_t>(1, scenes.size() * methods.size());
  for (const std::string& scene : scenes)
    for (const std::string& method : methods) {
      json row = {{"scene", scene}, {"method", method}, {"styles", json::array()}, {"styles_expected", styles_expected}};
      for (const auto& e : bench::metric_catalog()) {
        double sum = 0;
        int n = 0;
        json unavailable;
        for (const json& r : results) {
          if (r["scene"] != scene || r["method"] != method) continue;
          if (r[e.key].is_number()) sum += r[e.key].get<double>(), ++n;
          else if (unavailable.is_null()) unavailable = r[e.key];
        }
        row[e.key] = !unavailable.is_null() ? unavailable : n > 0 ? json(sum / n) : json{{"unavailable", "no finished cell"}};
      }
      for (const json& r : results)
        if (r["scene"] == scene && r["method"] == method) row["styles"].push_back(r["style"]);
      rows.push_back(row);
    }
  json missing_json = json::array();
  for (const Cell* c : missing) {
    const json s = read_state(m, c->id);
    missing_json.push_back({{"cell", c->id}, {"state", cell_state(m, *c)}, {"error", s.is_null() ? "" : s.value("error", "")}});
  }

  std::ostringstream md, csv, cells_csv;
  md << "# Style4D-Bench sweep: " << m.name << "\n\nRows: scene x method, each value the mean over the styles that finished ("
     << "`results.csv`: one row per cell). Best per scene in **bold**.\n\n| scene | method | styles |";
  for (const auto& e : bench::metric_catalog())
    if (in_table(e.key)) md << " " << e.label << (e.higher_is_better ? " ↑" : " ↓") << " |";
  md << "\n|---|---|---|";
  for (const auto& e : bench::metric_catalog())
    if (in_table(e.key)) md << "---|";
  md << "\n";
  std::vector<std::pair<std::string, std::string>> notes;
  for (const json& row : rows) {
    md << "| " << row["scene"].get<std::string>() << " | " << row["method"].get<std::string>() << " | " << row["styles"].size() << "/"
       << styles_expected << " |";
    for (const auto& e : bench::metric_catalog()) {
      if (!in_table(e.key)) continue;
      const json& v = row[e.key];
      if (!v.is_number()) {
        md << " n/a |";
        const std::string why = v.value("unavailable", "");
        if (row["styles"].empty()) continue;  // no finished cell: "Missing cells" says why
        if (std::find(notes.begin(), notes.end(), std::make_pair(e.key, why)) == notes.end()) notes.emplace_back(e.key, why);
        continue;
      }
      // Bold: the best of the scene's rows (two or more with a number), ties all bold.
      int numbers = 0;
      bool best = true;
      for (const json& other : rows) {
        if (other["scene"] != row["scene"] || !other[e.key].is_number()) continue;
        ++numbers;
        const double a = v.get<double>(), b = other[e.key].get<double>();
        if (e.higher_is_better ? b > a : b < a) best = false;
      }
      const bool bold = best && numbers > 1;
      md << (bold ? " **" : " ") << fixed(v.get<double>()) << (bold ? "** |" : " |");
    }
    md << "\n";
  }
  if (!notes.empty()) {
    md << "\nn/a: not computed, never estimated.\n\n";
    for (const auto& [key, why] : notes) md << "- `" << key << "`: " << why << "\n";
  }
  md << "\n## Missing cells\n\n";
  if (missing_json.empty()) md << "None: every bench cell finished.\n";
  for (const json& c : missing_json)
    md << "- `" << c["cell"].get<std::string>() << "`: " << c["state"].get<std::string>()
       << (c["error"].get<std::string>().empty() ? "" : " (" + c["error"].get<std::string>() + ")") << "\n";

  csv << "scene,method,styles";
  cells_csv << "cell,scene,method,style";
  for (const auto& e : bench::metric_catalog()) csv << "," << e.key, cells_csv << "," << e.key;
  csv << "\n", cells_csv << "\n";
  for (const json& row : rows) {
    csv << row["scene"].get<std::string>() << "," << row["method"].get<std::string>() << "," << row["styles"].size();
    for (const auto& e : bench::metric_catalog()) csv << "," << (row[e.key].is_number() ? exact(row[e.key].get<double>()) : "");
    csv << "\n";
  }
  for (const json& r : results) {
    cells_csv << r["cell"].get<std::string>() << "," << r["scene"].get<std::string>() << "," << r["method"].get<std::string>() << ","
              << r["style"].get<std::string>();
    for (const auto& e : bench::metric_catalog()) cells_csv << "," << (r[e.key].is_number() ? exact(r[e.key].get<double>()) : "");
    cells_csv << "\n";
  }
  fs::create_directories(out / "plots");
  util::write_file_atomic(out / "report.md", md.str());
  util::write_file_atomic(out / "report.csv", csv.str());
  util::write_file_atomic(out / "results.csv", cells_csv.str());
  util::write_file_atomic(out / "report.json", json{{"mode", "sweep"}, {"sweep", m.name}, {"rows", rows}, {"results", results},
                                                    {"missing", missing_json}, {"metrics_info", info}}.dump(2) + "\n");
  for (const auto& e : bench::metric_catalog()) {
    std::vector<std::vector<double>> values(methods.size(), std::vector<double>(scenes.size(), NAN));
    bool any = false;
    for (const json& row : rows) {
      if (!row[e.key].is_number()) continue;
      const size_t s = std::find(methods.begin(), methods.end(), row["method"]) - methods.begin();
      const size_t g = std::find(scenes.begin(), scenes.end(), row["scene"]) - scenes.begin();
      values[s][g] = row[e.key].get<double>();
      any = true;
    }
    if (any) bar_plot(out / "plots" / (e.key + ".png"), e.label + (e.higher_is_better ? " (higher is better)" : " (lower is better)"),
                      scenes, methods, values);
  }
  std::cerr << "sweep: report of " << finished.size() << " of " << finished.size() + missing.size() << " bench cells in "
            << (out / "report.md").string() << " (report.csv, report.json, results.csv, plots/)\n";
  for (const json& c : missing_json) std::cerr << "sweep: missing " << c["cell"].get<std::string>() << " (" << c["state"].get<std::string>() << ")\n";
  return static_cast<int>(missing.size());
}

}  // namespace s4d::cli::sweep
