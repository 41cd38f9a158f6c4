// The run mode's report (pooling a method's test-camera sequences, each key from its protocol) and
// the merge of several reports into one table, on hand-made results.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "s4d/bench/frames_report.h"
#include "s4d/bench/merge_report.h"
#include "s4d/bench/run_report.h"

namespace fs = std::filesystem;
namespace b = s4d::bench;

namespace {

fs::path fresh(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("s4d_bench_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// A result with the weight-free keys' per-frame values given (means filled in as evaluate_frames does).
b::MethodResult result(const std::string& name, std::map<std::string, std::vector<double>> per_frame) {
  b::MethodResult r;
  r.name = name;
  r.per_frame = std::move(per_frame);
  for (const auto& [key, v] : r.per_frame) {
    double s = 0;
    for (double x : v) s += x;
    r.means[key] = s / double(v.size());
    r.frame_count = std::max(r.frame_count, int(v.size()));
  }
  return r;
}

// A frames-mode report of one method on `scene`, written under `dir`.
fs::path frames_report(const fs::path& dir, const std::string& scene, const std::string& method, double uiqm) {
  b::ReportContext ctx{scene, "starry", "starry.png", {}};
  ctx.options.original = "original";
  b::MethodResult r = result(method, {{"uiqm", {uiqm}}, {"content_ssim", {0.5}}, {"warp_loss", {0.1}}});
  r.unavailable["psnr"] = "no ground truth";
  fs::create_directories(dir);
  std::ofstream(dir / "report.json") << b::report_json({r}, ctx).dump(2);
  return dir;
}

}  // namespace

TEST_CASE("a method's test cameras pool frame-weighted, and each headline key comes from its protocol") {
  const b::MethodResult cam0 = result("m", {{"uiqm", {1, 2, 3}}, {"content_ssim", {1, 1, 1}}, {"warp_loss", {0.5, 0.5}}});
  const b::MethodResult cam1 = result("m", {{"uiqm", {5}}, {"content_ssim", {0.5}}});
  b::MethodResult test = b::pool_sequences("m", {cam0, cam1});
  CHECK(test.frame_count == 4);
  CHECK(test.means.at("uiqm") == doctest::Approx(11.0 / 4));
  CHECK(test.means.at("content_ssim") == doctest::Approx(3.5 / 4));
  CHECK(test.per_frame.at("warp_loss").size() == 2);  // pairs within cam0 only
  CHECK_THROWS_AS(b::pool_sequences("m", {}), std::invalid_argument);

  b::MethodResult spiral = result("m", {{"uiqm", {9, 9}}, {"content_ssim", {0.2, 0.2}}, {"warp_loss", {0.25}}});
  spiral.unavailable["psnr"] = "the spiral path has no captured frames";
  test.unavailable["psnr"] = "no ground truth here";
  const b::RunMethodResult run{test, spiral, "starry", "starry.png"};
  const b::MethodResult h = b::headline(run);
  CHECK(h.means.at("uiqm") == doctest::Approx(11.0 / 4));
  CHECK(h.means.at("warp_loss") == doctest::Approx(0.25));
  CHECK(h.unavailable.at("psnr") == "no ground truth here");

  const fs::path out = fresh("run_report");
  b::RunReportContext ctx{"scene", "RUN", "DIR/renders", 2, {}};
  b::write_run_report(out, {run}, ctx);
  const nlohmann::json j = nlohmann::json::parse(read_text(out / "report.json"));
  CHECK(j.at("mode") == "run");
  const nlohmann::json& r = j.at("results")[0];
  CHECK(r.at("warp_loss").get<double>() == doctest::Approx(0.25));
  CHECK(r.at("protocols").at("test").at("warp_loss").get<double>() == doctest::Approx(0.5));
  CHECK(r.at("protocols").at("spiral").at("uiqm").get<double>() == doctest::Approx(9));
  CHECK(r.at("protocols").at("spiral").at("frames") == 2);
  CHECK(r.at("psnr").at("unavailable") == "no ground truth here");
  CHECK(j.at("metrics_info").at("warp_loss").at("protocol") == "spiral");
  CHECK(j.at("metrics_info").at("uiqm").at("protocol") == "test");
  CHECK(fs::exists(out / "plots" / "warp_loss.png"));
  CHECK(fs::exists(out / "report.md"));
}

TEST_CASE("merge builds one table from several reports and refuses mixed conventions and repeated rows") {
  const fs::path root = fresh("merge");
  const fs::path a = frames_report(root / "a", "flame", "ours", 1.0), c = frames_report(root / "c", "coffee", "ours", 3.0);
  const nlohmann::json merged = b::merge_reports({a, c / "report.json"});
  CHECK(merged.at("mode") == "merge");
  REQUIRE(merged.at("results").size() == 2);
  CHECK(merged.at("results")[0].at("scene") == "flame");
  CHECK(merged.at("results")[1].at("uiqm").get<double>() == doctest::Approx(3.0));
  CHECK(merged.at("results")[1].at("source") == (c / "report.json").string());
  CHECK(merged.at("inputs").at("reports").size() == 2);
  b::write_merged_report(root / "out", merged);
  const std::string md = read_text(root / "out" / "report.md");
  CHECK(md.find("| ours | flame |") != std::string::npos);
  CHECK(md.find("| ours | coffee |") != std::string::npos);
  CHECK(read_text(root / "out" / "report.csv").find("\"coffee\"") != std::string::npos);

  // The same row twice.
  const fs::path again = frames_report(root / "again", "flame", "ours", 2.0);
  try {
    b::merge_reports({a, again});
    FAIL("expected a refusal");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find("already in " + (a / "report.json").string()) != std::string::npos);
  }
  // A metric measured differently (another UIQM variant).
  nlohmann::json other = nlohmann::json::parse(read_text(c / "report.json"));
  other["metrics_info"]["uiqm"]["convention"] = "variant B";
  fs::create_directories(root / "b");
  std::ofstream(root / "b" / "report.json") << other.dump();
  try {
    b::merge_reports({a, root / "b"});
    FAIL("expected a refusal");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find("metrics_info.uiqm.convention") != std::string::npos);
  }
  CHECK_THROWS_WITH_AS(b::merge_reports({root / "missing"}), doctest::Contains("missing"), std::runtime_error);
}
