#include "s4d/bench/report_html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "s4d/data/webm_video.h"
#include "s4d/util/atomic_file.h"

namespace s4d::bench {

namespace {

namespace fs = std::filesystem;

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string base64(const std::string& bytes) {
  static const char kTable[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = static_cast<uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 2]);
    out += kTable[(v >> 18) & 63];
    out += kTable[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kTable[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kTable[v & 63] : '=';
  }
  return out;
}

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot read");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

// One metric's per-frame values, a polyline per method.
std::string curve_svg(const std::string& title, const std::vector<std::pair<std::string, std::vector<double>>>& series) {
  const double w = 640, h = 220, left = 60, right = 150, top = 24, bottom = 30;
  double lo = INFINITY, hi = -INFINITY;
  size_t n = 0;
  for (const auto& [name, v] : series)
    for (double x : v)
      if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x), n = std::max(n, v.size());
  if (!(lo <= hi) || n == 0) return "";
  if (hi == lo) hi = lo + 1;
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h << "\" role=\"img\" aria-label=\"" << escape(title)
    << "\"><text x=\"" << left << "\" y=\"16\" font-size=\"13\">" << escape(title) << "</text>"
    << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << w - left - right << "\" height=\"" << h - top - bottom
    << "\" fill=\"none\" stroke=\"#999\"/>"
    << "<text x=\"" << left - 4 << "\" y=\"" << top + 10 << "\" font-size=\"11\" text-anchor=\"end\">" << number(hi) << "</text>"
    << "<text x=\"" << left - 4 << "\" y=\"" << h - bottom << "\" font-size=\"11\" text-anchor=\"end\">" << number(lo) << "</text>"
    << "<text x=\"" << left << "\" y=\"" << h - 12 << "\" font-size=\"11\">0</text>"
    << "<text x=\"" << w - right << "\" y=\"" << h - 12 << "\" font-size=\"11\" text-anchor=\"end\">" << n - 1 << "</text>";
  for (size_t k = 0; k < series.size(); ++k) {
    const auto& v = series[k].second;
    s << "<polyline fill=\"none\" stroke-width=\"1.5\" stroke=\"" << kColours[k % 8] << "\" points=\"";
    for (size_t i = 0; i < v.size(); ++i) {
      if (!std::isfinite(v[i])) continue;
      const double x = left + (n > 1 ? static_cast<double>(i) / static_cast<double>(n - 1) : 0.5) * (w - left - right);
      const double y = top + (hi - v[i]) / (hi - lo) * (h - top - bottom);
      s << number(x) << "," << number(y) << " ";
    }
    s << "\"/><text x=\"" << w - right + 8 << "\" y=\"" << top + 12 + 16 * static_cast<double>(k) << "\" font-size=\"12\" fill=\""
      << kColours[k % 8] << "\">" << escape(series[k].first) << "</text>";
  }
  return s.str() + "</svg>";
}

struct VideoSource {
  std::string label;
  fs::path frames;
};

// The sequences to show side by side, one row per view: the original first, then each method.
std::vector<std::pair<std::string, std::vector<VideoSource>>> video_rows(const nlohmann::json& report) {
  std::vector<std::pair<std::string, std::vector<VideoSource>>> rows;
  const std::string mode = report.value("mode", "");
  const nlohmann::json& results = report.at("results");
  auto recorded = [](const nlohmann::json& j, const char* key) {
    return j.contains(key) && j.at(key).is_string() ? fs::path(j.at(key).get<std::string>()) : fs::path();
  };
  auto first_camera = [](const fs::path& test) {
    std::vector<fs::path> cams;
    if (fs::is_directory(test))
      for (const auto& e : fs::directory_iterator(test))
        if (e.is_directory()) cams.push_back(e.path());
    std::sort(cams.begin(), cams.end());
    return cams.empty() ? fs::path() : cams.front();
  };
  if (mode == "frames") {
    std::vector<VideoSource> row = {{"original", recorded(report.at("inputs"), "original")}};
    for (const auto& r : results)
      if (r.value("method", "") != "original") row.push_back({r.value("method", ""), recorded(r.at("inputs"), "frames")});
    rows.push_back({"the scored frames", row});
  } else if (mode == "run") {
    const fs::path renders = recorded(report.at("inputs"), "renders");
    std::vector<VideoSource> spiral = {{"original", renders / "original" / "spiral"}};
    const fs::path cam = first_camera(renders / "original" / "test");
    std::vector<VideoSource> test = {{"original", cam}};
    for (const auto& r : results) {
      if (r.value("method", "") == "original") continue;
      spiral.push_back({r.value("method", ""), recorded(r.at("inputs"), "spiral")});
      test.push_back({r.value("method", ""), cam.empty() ? fs::path() : recorded(r.at("inputs"), "test") / cam.filename()});
    }
    rows.push_back({"spiral (the freely moving camera; warp loss and DISTS)", spiral});
    if (!cam.empty()) rows.push_back({"test camera " + cam.filename().string() + " (fixed view over time)", test});
  }
  return rows;
}

const char* const kStyle = R"(
body { font-family: system-ui, sans-serif; margin: 1.5em; color: #222; }
table { border-collapse: collapse; font-size: 13px; }
th, td { border: 1px solid #ccc; padding: 3px 6px; text-align: right; vertical-align: top; }
th { background: #f3f3f3; cursor: pointer; }
td.name { text-align: left; }
td.na { color: #888; text-align: left; max-width: 16em; font-size: 11px; }
.videos { display: flex; gap: 10px; flex-wrap: wrap; }
.videos figure { margin: 0; text-align: center; }
.videos video { width: 320px; background: #000; image-rendering: pixelated; }
img.sheet { max-width: 100%; image-rendering: pixelated; }
)";

// Click a header to sort by it (numbers; n/a last); within a row of videos the first is the clock.
const char* const kScript = R"(
for (const th of document.querySelectorAll("#metrics th")) {
  th.addEventListener("click", () => {
    const col = th.cellIndex, body = document.querySelector("#metrics tbody");
    const asc = th.dataset.sort !== "asc";
    for (const other of document.querySelectorAll("#metrics th")) delete other.dataset.sort;
    th.dataset.sort = asc ? "asc" : "desc";
    const key = (tr) => { const c = tr.cells[col]; return c.dataset.value === undefined ? c.textContent : Number(c.dataset.value); };
    const rows = Array.from(body.rows).sort((a, b) => {
      const x = key(a), y = key(b);
      if (typeof x === "number" && Number.isNaN(x)) return 1;
      if (typeof y === "number" && Number.isNaN(y)) return -1;
      return (x < y ? -1 : x > y ? 1 : 0) * (asc ? 1 : -1);
    });
    for (const r of rows) body.append(r);
  });
}
for (const row of document.querySelectorAll(".videos")) {
  const [clock, ...others] = row.querySelectorAll("video");
  if (!clock) continue;
  const follow = () => { for (const v of others) if (Math.abs(v.currentTime - clock.currentTime) > 0.05) v.currentTime = clock.currentTime; };
  clock.addEventListener("timeupdate", follow);
  clock.addEventListener("seeked", follow);
  clock.addEventListener("play", () => { for (const v of others) v.play().catch(() => {}); });
  clock.addEventListener("pause", () => { for (const v of others) { v.pause(); v.currentTime = clock.currentTime; } });
  row.parentElement.querySelector("button").addEventListener("click", () => {
    for (const v of row.querySelectorAll("video")) v.currentTime = 0;
    clock.play().catch(() => {});
  });
}
)";

}  // namespace

void write_report_html(const fs::path& out, const nlohmann::json& report, int max_video_frames) {
  std::ostringstream h;
  h << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Style4D-Bench report</title><style>" << kStyle
    << "</style></head><body>\n<h1>Style4D-Bench report</h1>\n<p>Mode: " << escape(report.value("mode", "")) << ". ";
  const nlohmann::json& info = report.at("metrics_info");
  const nlohmann::json& results = report.at("results");
  h << results.size() << " result(s). Click a column to sort; hover a header for its implementation and convention.</p>\n";

  // The metric table, columns in the report's key order.
  std::vector<std::string> keys;
  for (auto it = info.begin(); it != info.end(); ++it) keys.push_back(it.key());
  h << "<table id=\"metrics\"><thead><tr><th>method</th><th>scene</th><th>style</th>";
  for (const std::string& k : keys) {
    const nlohmann::json& e = info.at(k);
    const bool higher = e.value("direction", "") == "higher";
    h << "<th title=\"" << escape(e.value("impl", "") + "; " + e.value("convention", "")) << "\">" << escape(k) << " "
      << (higher ? "&uarr; higher is better" : "&darr; lower is better") << "</th>";
  }
  h << "</tr></thead><tbody>\n";
  for (const auto& r : results) {
    h << "<tr><td class=\"name\">" << escape(r.value("method", "")) << "</td><td class=\"name\">" << escape(r.value("scene", ""))
      << "</td><td class=\"name\">" << escape(r.value("style", "")) << "</td>";
    for (const std::string& k : keys) {
      const nlohmann::json v = r.contains(k) ? r.at(k) : nlohmann::json();
      if (v.is_number()) h << "<td data-value=\"" << number(v.get<double>()) << "\">" << number(v.get<double>()) << "</td>";
      else
        h << "<td class=\"na\" data-value=\"NaN\">n/a, because "
          << escape(v.is_object() && v.contains("unavailable") ? v.at("unavailable").get<std::string>() : "the report has no value") << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</tbody></table>\n";

  // Per-frame curves.
  h << "<h2>Per-frame values</h2>\n";
  bool any_curve = false;
  for (const std::string& k : keys) {
    std::vector<std::pair<std::string, std::vector<double>>> series;
    for (const auto& r : results)
      if (r.contains("per_frame") && r.at("per_frame").contains(k))
        series.push_back({r.value("method", "") + " / " + r.value("scene", ""), r.at("per_frame").at(k).get<std::vector<double>>()});
    const std::string svg = series.empty() ? "" : curve_svg(k + (k == "warp_loss" ? " per frame pair" : " per frame"), series);
    if (!svg.empty()) h << svg << "\n", any_curve = true;
  }
  if (!any_curve) h << "<p>n/a, because the report holds no per-frame values.</p>\n";

  // Videos, embedded: the page must play them from the file alone.
  h << "<h2>Videos</h2>\n";
  const auto rows = video_rows(report);
  if (rows.empty()) h << "<p>n/a, because a merged report has no frames of its own: each source report's page shows them.</p>\n";
  const fs::path scratch = out / ".report_html_video.webm";
  for (const auto& [title, sources] : rows) {
    h << "<section><h3>" << escape(title) << " <button>Replay</button></h3><div class=\"videos\">";
    for (const VideoSource& v : sources) {
      h << "<figure>";
      if (v.frames.empty() || !fs::exists(v.frames)) {
        h << "<p>n/a, because " << escape(v.frames.empty() ? std::string("no sequence was recorded") : v.frames.string() + " no longer exists")
          << "</p>";
      } else {
        data::encode_webm(v.frames, max_video_frames, 30, scratch);
        h << "<video muted loop autoplay playsinline src=\"data:video/webm;base64," << base64(read_bytes(scratch)) << "\"></video>";
        fs::remove(scratch);
      }
      h << "<figcaption>" << escape(v.label) << "</figcaption></figure>";
    }
    h << "</div></section>\n";
  }

  h << "<h2>Contact sheet</h2>\n";
  if (fs::exists(out / "contact_sheet.png"))
    h << "<img class=\"sheet\" alt=\"contact sheet\" src=\"data:image/png;base64," << base64(read_bytes(out / "contact_sheet.png")) << "\">\n";
  else h << "<p>n/a, because this report has no contact sheet (a merged report).</p>\n";
  h << "<script>" << kScript << "</script>\n</body></html>\n";
  util::write_file_atomic(out / "report.html", h.str());
}

}  // namespace s4d::bench
