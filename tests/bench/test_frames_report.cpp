// The frames mode of `style4d bench` through its library (s4d_bench_report), on PNG videos the test
// writes: a textured scene moving 2 px per frame, a "copy" method (the original itself) and an
// "invert" method (1 - value). Checks METRICS.md's key contract, the hand-known values (copy: SSIM 1,
// PSNR at the cap against itself), and the report files.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../metrics/metrics_test_util.h"
#include "s4d/bench/frames_report.h"
#include "s4d/bench/line_plot.h"
#include "s4d/bench/metric_catalog.h"
#include "s4d/io/psnr.h"

namespace fs = std::filesystem;
namespace b = s4d::bench;

namespace {

fs::path fresh(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("s4d_bench_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write_video(const fs::path& dir, int frames, bool invert) {
  fs::create_directories(dir);
  for (int t = 0; t < frames; ++t) {
    auto im = s4d::test::image_of(64, 48, [&](double x, double y, int c) { return s4d::test::texture(x - 2.0 * t, y, c); });
    if (invert)
      for (float& v : im.data) v = 1.0f - v;
    s4d::io::write_png(dir / ("frame_" + std::to_string(1000 + t) + ".png"), im);
  }
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The last cell of the Markdown table row starting with `row`, trimmed ("" when there is no such row).
std::string last_cell(const std::string& md, const std::string& row) {
  const size_t start = md.find(row);
  if (start == std::string::npos) return "";
  const std::string line = md.substr(start, md.find('\n', start) - start);
  const size_t end = line.find_last_of('|'), begin = line.find_last_of('|', end - 1) + 1;
  std::string cell = line.substr(begin, end - begin);
  cell.erase(0, cell.find_first_not_of(' '));
  cell.erase(cell.find_last_not_of(' ') + 1);
  return cell;
}

// Frames of one constant grey level each (levels / 255 are exact in PNG), for hand-computed warp losses.
void write_levels(const fs::path& dir, const std::vector<int>& levels) {
  fs::create_directories(dir);
  for (size_t t = 0; t < levels.size(); ++t) {
    const float v = float(levels[t]) / 255.0f;
    s4d::io::write_png(dir / ("frame_" + std::to_string(1000 + t) + ".png"), s4d::test::constant_image(16, 12, v, v, v));
  }
}

// fw_NNNN.exr / bw_NNNN.exr of constant horizontal flows for pair `pair`.
void write_flow_pair(const fs::path& dir, int pair, float fw_u, float bw_u) {
  fs::create_directories(dir);
  char fw[32], bw[32];
  std::snprintf(fw, sizeof fw, "fw_%04d.exr", pair);
  std::snprintf(bw, sizeof bw, "bw_%04d.exr", pair);
  const std::vector<float> fu(16 * 12, fw_u), bu(16 * 12, bw_u), v(16 * 12, 0.0f);
  s4d::io::write_exr(dir / fw, 16, 12, {{"u", fu.data()}, {"v", v.data()}});
  s4d::io::write_exr(dir / bw, 16, 12, {{"u", bu.data()}, {"v", v.data()}});
}

struct Scene {
  fs::path root, original, invert, style;
};

Scene make_scene(const std::string& name, int frames = 5) {
  Scene s{fresh(name), {}, {}, {}};
  s.original = s.root / "original", s.invert = s.root / "invert", s.style = s.root / "starry.png";
  write_video(s.original, frames, false);
  write_video(s.invert, frames, true);
  s4d::io::write_png(s.style, s4d::test::lcg_image(32, 32));
  return s;
}

}  // namespace

TEST_CASE("frames report holds every metric key as a number or an explained unavailable") {
  const Scene s = make_scene("contract");
  b::ReportContext ctx{"moving", "starry", s.style, {}};
  ctx.options.original = s.original;
  ctx.options.ground_truth = s.original;
  std::vector<b::MethodResult> methods = {b::evaluate_frames("copy", s.original, ctx.options),
                                          b::evaluate_frames("invert", s.invert, ctx.options)};
  const fs::path out = s.root / "report";
  b::write_frames_report(out, methods, ctx);

  const auto report = nlohmann::json::parse(read_text(out / "report.json"));
  REQUIRE(report.at("results").size() == 2);
  for (const auto& r : report.at("results")) {
    for (const auto& e : b::metric_catalog()) {
      INFO("method " << r.at("method") << ", key " << e.key);
      REQUIRE(r.contains(e.key));
      const auto& v = r.at(e.key);
      CHECK((v.is_number() || (v.is_object() && v.at("unavailable").is_string() && !v.at("unavailable").get<std::string>().empty())));
      // With ground truth and 5 frames every native key scores, but psnr only on the original's own row:
      // it is the reconstruction's, one value per run.
      const bool own_psnr = e.key != "psnr" || r.at("method") == "copy";
      CHECK(v.is_number() == (!e.unavailable.has_value() && own_psnr));
      CHECK(report.at("metrics_info").at(e.key).at("impl").is_string());
      CHECK(report.at("metrics_info").at(e.key).at("convention").is_string());
    }
    CHECK(r.at("per_frame").at("warp_loss").size() == 4);
    CHECK(r.at("per_frame").at("uiqm").size() == 5);
  }
  const auto& copy = report.at("results")[0];
  CHECK(copy.at("content_ssim").get<double>() == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(copy.at("psnr").get<double>() == doctest::Approx(s4d::io::kPsnrCapDb).epsilon(1e-12));
  // The 2 px shift per frame, DIS flow on the original, warp of the copy: measured 0.00087 (mostly the
  // clamped strip at the image edge); 0.005 leaves room for DIS's fit.
  CHECK(copy.at("warp_loss").get<double>() < 0.005);
  CHECK(report.at("results")[1].at("content_ssim").get<double>() < 0.5);
  // The inverted render is not the reconstruction: no copy of the original's 100 dB, the reason instead.
  CHECK(report.at("results")[1].at("psnr").at("unavailable") == b::kPsnrPerRun);
  CHECK(report.at("results")[0].at("style").get<std::string>() == "starry");
  CHECK(report.at("metrics_info").at("ckdn").at("direction") == "higher");

  const std::string md = read_text(out / "report.md");
  CHECK(md.find("| method | scene |") != std::string::npos);
  CHECK(md.find("| copy | moving |") != std::string::npos);
  CHECK(md.find("CKDN_model_best-38b27dc6.pth") != std::string::npos);
  // psnr is the table's last column: the copy row shows its own 100 dB, the invert row "-", and the
  // header and notes say the value is per run.
  CHECK(last_cell(md, "| copy | moving |") == "100.0000");
  CHECK(last_cell(md, "| invert | moving |") == "-");
  CHECK(md.find("PSNR (original scene, per run) ↑") != std::string::npos);
  CHECK(md.find("- `psnr` (-): per run, not per style") != std::string::npos);
  const std::string csv = read_text(out / "report.csv");
  CHECK(csv.find("\"invert\",\"moving\",\"starry\",") != std::string::npos);
  CHECK(csv.substr(csv.find("\"invert\"")).find(",\n") != std::string::npos);  // empty psnr field ends the row
  CHECK(csv.rfind("method,scene,style,uiqm,clipiqa_plus,", 0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 3);
  for (const char* plot : {"uiqm", "content_ssim", "warp_loss", "psnr"}) {
    const auto png = s4d::io::read_png(out / "plots" / (std::string(plot) + ".png"));
    CHECK(png.width == 800);
  }
  const auto sheet = s4d::io::read_png(out / "contact_sheet.png");
  CHECK(sheet.width == 160 + 4 * 256);  // label column + 4 sample frames
  CHECK(sheet.height == 24 + 3 * 192);  // header + original, copy, invert rows of 64x48 scaled to 256 wide
}

TEST_CASE("without ground truth psnr is unavailable and says what to supply") {
  const Scene s = make_scene("no_truth", 3);
  b::FramesOptions o;
  o.original = s.original;
  b::ReportContext ctx{"moving", "starry", s.style, o};
  const auto report = b::report_json({b::evaluate_frames("copy", s.original, o)}, ctx);
  const auto& psnr = report.at("results")[0].at("psnr");
  REQUIRE(psnr.is_object());
  CHECK(psnr.at("unavailable").get<std::string>().find("--ground-truth") != std::string::npos);
}

TEST_CASE("frames and original of different lengths are refused, naming both") {
  const Scene s = make_scene("lengths", 3);
  fs::remove(s.invert / "frame_1002.png");
  b::FramesOptions o;
  o.original = s.original;
  try {
    b::evaluate_frames("invert", s.invert, o);
    FAIL("no error");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find(s.invert.string()) != std::string::npos);
    CHECK(std::string(e.what()).find("2 frames") != std::string::npos);
  }
  CHECK_THROWS_AS(b::evaluate_frames("x", s.root / "missing", o), std::runtime_error);
}

TEST_CASE("exact flow is read from fw_NNNN.exr and bw_NNNN.exr, and a missing file is named") {
  const Scene s = make_scene("exact_flow", 2);
  b::FramesOptions o;
  o.original = s.original;
  o.flow = b::FlowSource::exact;
  o.flow_dir = s.root / "flow";
  fs::create_directories(o.flow_dir);
  CHECK_THROWS_WITH_AS(b::evaluate_frames("copy", s.original, o), doctest::Contains("fw_0000.exr"), std::runtime_error);
  const std::vector<float> u(64 * 48, 2.0f), v(64 * 48, 0.0f), bu(64 * 48, -2.0f);
  s4d::io::write_exr(o.flow_dir / "fw_0000.exr", 64, 48, {{"u", u.data()}, {"v", v.data()}});
  s4d::io::write_exr(o.flow_dir / "bw_0000.exr", 64, 48, {{"u", bu.data()}, {"v", v.data()}});
  const auto r = b::evaluate_frames("copy", s.original, o);
  // Content moves +2 px: the exact flow warps back exactly except the 2 clamped columns at the right
  // edge; measured 0.0018.
  CHECK(r.means.at("warp_loss") < 0.005);
}

TEST_CASE("a frame pair occluded at every pixel is left out of the warp loss, and with no pair left it is unavailable") {
  const fs::path root = fresh("occluded_pairs");
  write_levels(root / "video", {51, 153, 102});
  b::FramesOptions o;
  o.original = root / "video";
  o.flow = b::FlowSource::exact;
  o.flow_dir = root / "flow";
  // Pair 0: zero flow both ways, nothing occluded; the frames differ by (153 - 51) / 255 = 0.4 at every
  // pixel. Pair 1: forward and backward both +5 px: |5 + 5|^2 = 100 > 0.01 (25 + 25) + 0.5 everywhere,
  // so every pixel is occluded. The mean is pair 0's 0.4 alone; counting pair 1 as 0 gave 0.2.
  write_flow_pair(o.flow_dir, 0, 0.0f, 0.0f);
  write_flow_pair(o.flow_dir, 1, 5.0f, 5.0f);
  const b::MethodResult one = b::evaluate_frames("video", o.original, o);
  REQUIRE(one.means.count("warp_loss") == 1);
  CHECK(one.means.at("warp_loss") == doctest::Approx(0.4).epsilon(1e-6));  // 8-bit levels / 255 are exact; float sums
  CHECK(one.per_frame.at("warp_loss").size() == 1);
  CHECK(one.unavailable.count("warp_loss") == 0);

  // Both pairs occluded everywhere: no score, and the reason says so.
  write_flow_pair(o.flow_dir, 0, 5.0f, 5.0f);
  const b::MethodResult none = b::evaluate_frames("video", o.original, o);
  CHECK(none.means.count("warp_loss") == 0);
  CHECK(none.per_frame.count("warp_loss") == 0);
  REQUIRE(none.unavailable.count("warp_loss") == 1);
  CHECK(none.unavailable.at("warp_loss").find("every one of the 2 frame pairs is occluded") != std::string::npos);
  const b::ReportContext ctx{"grey", "none", {}, o};
  const auto report = b::report_json({none}, ctx);
  CHECK(report.at("results")[0].at("warp_loss").at("unavailable").get<std::string>().find("occluded") != std::string::npos);
}

TEST_CASE("line plot refuses an empty series") {
  CHECK_THROWS_AS(b::line_plot("t", "x", "y", {{"a", {}}}), std::invalid_argument);
  CHECK_THROWS_AS(b::line_plot("t", "x", "y", {}), std::invalid_argument);
}
