// s4d_pareto_report POINTS.jsonl OUT_DIR: the speed/accuracy report of a sweep (bench/pareto_sweep.sh).
// Each line of POINTS.jsonl is one setting: {"label": ..., "seconds": ..., "device_peak_mib": ...,
// "test_psnr": ..., "test_ssim": ..., "warp_error" and "warp_error_2d" for stylized runs, more keys kept
// as they are}. Writes OUT_DIR/pareto.json (every
// point and, per cost, the labels on the front), pareto.md (a table by time with the fronts marked)
// and one plot per cost, pareto_seconds.png and pareto_device_peak_mib.png (test PSNR against it).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "s4d/bench/pareto.h"
#include "s4d/io/image_io.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kCosts[] = {"seconds", "device_peak_mib"};
constexpr const char* kQuality = "test_psnr";

std::vector<json> read_points(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::vector<json> points;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    json j;
    try {
      j = json::parse(line);
    } catch (const json::exception& e) {
      throw std::runtime_error(file.string() + ":" + std::to_string(n) + ": not JSON: " + e.what());
    }
    for (const char* key : {"label", "seconds", "device_peak_mib", kQuality})
      if (!j.contains(key)) throw std::runtime_error(file.string() + ":" + std::to_string(n) + ": missing \"" + key + "\"");
    points.push_back(std::move(j));
  }
  if (points.empty()) throw std::runtime_error(file.string() + ": no points");
  return points;
}

std::vector<s4d::bench::TradePoint> trade(const std::vector<json>& points, const std::string& cost) {
  std::vector<s4d::bench::TradePoint> t;
  for (const json& p : points) t.push_back({p.at("label"), p.at(cost).get<double>(), p.at(kQuality).get<double>()});
  return t;
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

std::string table(const std::vector<json>& points, const json& fronts) {
  std::vector<size_t> order(points.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return points[a]["seconds"] < points[b]["seconds"]; });
  // Stylized sweeps also carry the spiral render's warp error and the 2D stylizer's on the same path.
  const bool warp = std::any_of(points.begin(), points.end(), [](const json& p) { return p.contains("warp_error"); });
  std::ostringstream md;
  md << "| setting | seconds | device MiB | test PSNR (dB) | test SSIM |" << (warp ? " warp error (spiral, exact flow) | 2D stylizer's (same spiral) |" : "")
     << " front (time) | front (memory) |\n|---|---|---|---|---|" << (warp ? "---|---|" : "") << "---|---|\n";
  auto optional = [](const json& p, const char* key, int digits) {
    return p.contains(key) ? fixed(p[key].get<double>(), digits) : std::string();
  };
  auto on = [&](const char* cost, const std::string& label) {
    const json& f = fronts.at(cost);
    return std::find(f.begin(), f.end(), label) != f.end() ? "yes" : "";
  };
  for (size_t i : order) {
    const json& p = points[i];
    const std::string label = p.at("label");
    md << "| " << label << " | " << optional(p, "seconds", 0) << " | " << optional(p, "device_peak_mib", 1) << " | "
       << optional(p, kQuality, 2) << " | " << optional(p, "test_ssim", 3) << " | ";
    if (warp) md << optional(p, "warp_error", 4) << " | " << optional(p, "warp_error_2d", 4) << " | ";
    md << on("seconds", label) << " | " << on("device_peak_mib", label) << " |\n";
  }
  return md.str();
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc != 3) {
    std::cerr << "usage: s4d_pareto_report POINTS.jsonl OUT_DIR\n";
    return 2;
  }
  const std::vector<json> points = read_points(argv[1]);
  const fs::path out = argv[2];
  fs::create_directories(out);
  json fronts;
  for (const char* cost : kCosts) {
    const auto t = trade(points, cost);
    json labels = json::array();
    for (size_t i : s4d::bench::pareto_front(t)) labels.push_back(t[i].label);
    fronts[cost] = labels;
    s4d::io::write_png(out / (std::string("pareto_") + cost + ".png"),
                       s4d::bench::pareto_plot(std::string("test PSNR against ") + cost, cost, "test PSNR (dB)", t, true));
  }
  std::ofstream(out / "pareto.json") << json{{"points", points}, {"fronts", fronts}}.dump(2) << "\n";
  std::ofstream(out / "pareto.md") << "# Speed/accuracy trade\n\n" << table(points, fronts)
                                   << "\n![time](pareto_seconds.png)\n![memory](pareto_device_peak_mib.png)\n";
  std::cout << table(points, fronts);
  return 0;
} catch (const std::exception& e) {
  std::cerr << "s4d_pareto_report: " << e.what() << "\n";
  return 1;
}
