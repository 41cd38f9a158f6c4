// The pyiqa bridge's protocol (bench/report/pyiqa_bridge.cpp, bridge_process.cpp) with a stand-in
// script run by python3 (bridge_stand_in.h): the numbers it computes from the frame files reach
// the result and report.json; a crash, a metric's error, one sequence's error, a short list, invalid
// JSON and a missing interpreter each make the affected keys unavailable with the reason. No pyiqa
// needed.
#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../metrics/metrics_test_util.h"
#include "bridge_stand_in.h"
#include "s4d/bench/frames_report.h"
#include "s4d/bench/pyiqa_bridge.h"

namespace fs = std::filesystem;
namespace b = s4d::bench;

namespace {

struct BridgeScene {
  fs::path root;
  std::vector<std::vector<s4d::io::ImageF>> videos;  // as the PNG files hold them (8-bit levels)
  s4d::io::ImageF style;
  std::vector<b::BridgeSequence> seqs;
  b::BridgeOptions options;
};

// "<prefix><n>" (appending avoids GCC 12's false -Wrestrict on a literal + std::to_string).
std::string numbered(std::string prefix, int n) {
  prefix += std::to_string(n);
  return prefix;
}

double mean(const s4d::io::ImageF& im) {
  double s = 0;
  for (float v : im.data) s += v;
  return s / double(im.data.size());
}

// Two sequences of 3 and 2 frames (moving textures of different brightness) and a style image.
BridgeScene make_bridge_scene(const std::string& name) {
  BridgeScene s;
  s.root = fs::temp_directory_path() / numbered("s4d_bridge_" + name + "_", int(::getpid()));
  fs::remove_all(s.root);
  fs::create_directories(s.root);
  for (int v = 0; v < 2; ++v) {
    const fs::path dir = s.root / numbered("video", v);
    fs::create_directories(dir);
    std::vector<fs::path> files;
    s.videos.emplace_back();
    for (int t = 0; t < 3 - v; ++t) {
      const auto im = s4d::test::image_of(12, 9, [&](double x, double y, int c) {
        return 0.3 * v + 0.6 * s4d::test::texture(x - 3.0 * t, y, c);
      });
      files.push_back(dir / (numbered("f", t) + ".png"));
      s4d::io::write_png(files.back(), im);
      s.videos.back().push_back(s4d::io::read_png(files.back()));
    }
    s.seqs.push_back({numbered("seq", v), b::frame_files(dir, s.root / "decoded"), s.root / "style.png", b::bridge_keys()});
  }
  s4d::io::write_png(s.root / "style.png", s4d::test::lcg_image(8, 8));
  s.style = s4d::io::read_png(s.root / "style.png");
  std::ofstream(s.root / "stand_in.py") << s4d::test::kBridgeStandIn;
  s.options = {"python3", s.root / "stand_in.py", s.root / "bridge", b::bridge_keys()};
  return s;
}

struct Mode {
  explicit Mode(const char* m) { ::setenv("S4D_STAND_IN_MODE", m, 1); }
  ~Mode() { ::unsetenv("S4D_STAND_IN_MODE"); }
};

}  // namespace

TEST_CASE("the bridge's numbers flow from the script's process into results and report.json") {
  const BridgeScene s = make_bridge_scene("numbers");
  const b::BridgeOutcome out = b::run_bridge(s.options, s.seqs);
  REQUIRE(out.errors.empty());
  CHECK(out.versions.at("stand_in") == "1");
  for (size_t v = 0; v < 2; ++v) {
    const auto& values = out.values.at(s.seqs[v].id);
    const auto& frames = s.videos[v];
    REQUIRE(values.at("musiq").size() == frames.size());
    REQUIRE(values.at("dists").size() == frames.size() - 1);
    for (size_t t = 0; t < frames.size(); ++t) {
      // 8-bit levels / 255 summed in double (Python) and from float (here): measured 1.8e-8.
      CHECK(std::abs(values.at("musiq")[t] - mean(frames[t])) < 1e-6);
      CHECK(std::abs(values.at("ckdn")[t] - (mean(frames[t]) - mean(s.style))) < 1e-6);
    }
    double diff = 0;
    for (size_t k = 0; k < frames[0].data.size(); ++k) diff += std::abs(frames[1].data[k] - frames[0].data[k]);
    CHECK(std::abs(values.at("dino_score")[0] - diff / double(frames[0].data.size())) < 1e-6);
  }
  // The request the script read lists every frame file.
  std::ifstream req(s.options.work_dir / "request.json");
  const auto request = nlohmann::json::parse(req);
  CHECK(request.at("protocol") == b::kBridgeProtocol);
  CHECK(request.at("sequences")[0].at("frames").size() == 3);

  // Into a method's result and the report: the mean over frames, marked as the bridge's.
  b::MethodResult r;
  r.name = "m";
  r.means = {{"uiqm", 1}, {"content_ssim", 1}, {"warp_loss", 0}, {"psnr", 30}};
  b::apply_bridge(out, "seq0", b::bridge_keys(), r);
  b::FramesOptions o;
  for (const auto& k : b::bridge_keys()) o.bridged[k] = b::bridge_impl(s.options, out);
  const auto report = b::report_json({r}, {"scene", "style", s.root / "style.png", o});
  const auto& row = report.at("results")[0];
  const double expected = (mean(s.videos[0][0]) + mean(s.videos[0][1]) + mean(s.videos[0][2])) / 3;
  CHECK(std::abs(row.at("clipiqa_plus").get<double>() - expected) < 1e-6);
  CHECK(row.at("per_frame").at("dists").size() == 2);
  CHECK(report.at("metrics_info").at("musiq").at("impl").get<std::string>().find("pyiqa bridge: python3") == 0);
  CHECK(report.at("metrics_info").at("dino_score").at("convention").get<std::string>().find("mean over pairs") != std::string::npos);
  CHECK(row.at("content_lpips").at("unavailable").get<std::string>().find("--metric-weights") != std::string::npos);
  fs::remove_all(s.root);
}

TEST_CASE("every failure of the bridge makes the affected keys unavailable with the reason") {
  const BridgeScene s = make_bridge_scene("failures");
  auto reason = [&](const b::BridgeOutcome& o, const std::string& seq, const std::string& key) {
    b::MethodResult r;
    b::apply_bridge(o, seq, b::bridge_keys(), r);
    CHECK(r.means.count(key) == 0);
    return r.unavailable.count(key) ? r.unavailable.at(key) : std::string("(no reason)");
  };
  {
    const Mode m("crash");
    const auto o = b::run_bridge(s.options, s.seqs);
    CHECK(o.values.empty());
    const std::string why = reason(o, "seq1", "qalign");
    CHECK(why.find("exited with code 3") != std::string::npos);
    CHECK(why.find("stand-in: boom") != std::string::npos);
  }
  {
    const Mode m("error");
    const auto o = b::run_bridge(s.options, s.seqs);
    CHECK(reason(o, "seq0", "musiq") == "pyiqa bridge: no MUSIQ weights here");
    CHECK(o.values.at("seq0").count("musiq_paq2piq") == 1);  // the other keys still score
  }
  {
    const Mode m("seq_error");
    const auto o = b::run_bridge(s.options, s.seqs);
    CHECK(reason(o, "seq0", "ckdn") == "pyiqa bridge: frame 2 is unreadable");
    CHECK(o.values.at("seq1").count("ckdn") == 1);  // the other sequence keeps its values
  }
  {
    const Mode m("short");
    const auto o = b::run_bridge(s.options, s.seqs);
    CHECK(reason(o, "seq0", "clipiqa_plus").find("holds 2 values for 3 frames, expected 3") != std::string::npos);
  }
  {
    const Mode m("garbage");
    CHECK(reason(b::run_bridge(s.options, s.seqs), "seq0", "ckdn").find("is not valid JSON") != std::string::npos);
  }
  b::BridgeOptions missing = s.options;
  missing.python = s.root / "no-such-python";
  CHECK(reason(b::run_bridge(missing, s.seqs), "seq1", "dists").find("cannot start") != std::string::npos);
  // A 1-frame sequence gets no pair values: unavailable, not a made-up 0.
  b::BridgeSequence one = s.seqs[0];
  one.frames.resize(1);
  const auto o = b::run_bridge(s.options, {one});
  CHECK(reason(o, "seq0", "dists") == "needs at least 2 frames");
  fs::remove_all(s.root);
}

TEST_CASE("the embedded bridge script is tools/pyiqa_bridge.py") {
  std::ifstream f(fs::path(S4D_SOURCE_DIR) / "tools" / "pyiqa_bridge.py");
  std::stringstream text;
  text << f.rdbuf();
  REQUIRE(!text.str().empty());
  CHECK(b::embedded_bridge_script() == text.str());
}
