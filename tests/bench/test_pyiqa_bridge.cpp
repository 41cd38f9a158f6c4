// The pyiqa bridge (tools/pyiqa_bridge.py, embedded; bench/report/pyiqa_bridge.cpp, bridge_process.cpp)
// run by python3 against a fake pyiqa (fake_pyiqa.h) that enforces pyiqa's interface and scores from
// the pixels: the numbers reach the result and report.json; pyiqa missing, a metric that cannot be
// created, a failing call on one sequence, a score outside pyiqa's range and an inverted direction
// each make only the affected keys unavailable with the reason. Scripts the test writes check the
// protocol's own failures: a crash, invalid JSON, a short list, a missing interpreter. dino_score
// through torch.hub on a fake DINO (tests/bench/fake_dino) needs torch; the rest does not.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../metrics/metrics_test_util.h"
#include "fake_pyiqa.h"
#include "s4d/bench/frames_report.h"
#include "s4d/bench/pyiqa_bridge.h"

namespace fs = std::filesystem;
namespace b = s4d::bench;
using s4d::test::fake_pyiqa_score;
using s4d::test::FakePyiqa;

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

// Two sequences of 3 and 2 frames (moving textures of different brightness and colour) and a style
// image; the embedded bridge script.
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
        return 0.1 * c + 0.3 * v + 0.5 * s4d::test::texture(x - 3.0 * t, y, c);
      });
      files.push_back(dir / (numbered("f", t) + ".png"));
      s4d::io::write_png(files.back(), im);
      s.videos.back().push_back(s4d::io::read_png(files.back()));
    }
    s.seqs.push_back({numbered("seq", v), b::frame_files(dir, s.root / "decoded"), s.root / "style.png", b::bridge_keys()});
  }
  s4d::io::write_png(s.root / "style.png", s4d::test::lcg_image(8, 8));
  s.style = s4d::io::read_png(s.root / "style.png");
  s.options = {"python3", std::nullopt, s.root / "bridge", b::bridge_keys()};
  return s;
}

// The reason (sequence, key) is unavailable after the outcome is applied; "(no reason)" when it has a value.
std::string reason(const b::BridgeOutcome& o, const std::string& seq, const std::string& key) {
  b::MethodResult r;
  b::apply_bridge(o, seq, b::bridge_keys(), r);
  return r.unavailable.count(key) ? r.unavailable.at(key) : std::string("(no reason)");
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("the bridge's numbers flow from pyiqa's calls into results and report.json") {
  const BridgeScene s = make_bridge_scene("numbers");
  const FakePyiqa fake;
  const b::BridgeOutcome out = b::run_bridge(s.options, s.seqs);
  // DINO comes through torch.hub, not pyiqa: it fails alone (no hubconf.py there, or no torch).
  CHECK(out.errors.at("seq0").size() == 1);
  CHECK(has(reason(out, "seq0", "dino_score"), "pyiqa bridge: "));
  CHECK(out.versions.at("pyiqa") == "0.0-fake");
  CHECK(has(out.versions.at("dists").get<std::string>(), "lower_better True, score range 0, 1"));
  for (size_t v = 0; v < 2; ++v) {
    const auto& values = out.values.at(s.seqs[v].id);
    const auto& frames = s.videos[v];
    for (const char* key : {"clipiqa_plus", "musiq", "qalign", "musiq_paq2piq", "ckdn"}) {
      INFO(key);
      REQUIRE(values.at(key).size() == frames.size());
      // 8-bit levels / 255 summed in double (Python) and from float (here): measured 4.5e-8 relative (musiq_paq2piq).
      for (size_t t = 0; t < frames.size(); ++t) {
        const double expected = fake_pyiqa_score(key, frames[t], &s.style);
        CHECK(std::abs(values.at(key)[t] - expected) <= 1e-6 * expected);
      }
    }
    // DISTS(f_t+1, f_t): the later frame is pyiqa's target.
    REQUIRE(values.at("dists").size() == frames.size() - 1);
    const double d = fake_pyiqa_score("dists", frames[1], &frames[0]);
    CHECK(std::abs(values.at("dists")[0] - d) <= 1e-6 * d);
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
  for (const auto& k : b::bridge_keys()) o.bridged[k] = b::bridge_impl(s.options, out, k);
  const auto report = b::report_json({r}, {"scene", "style", s.root / "style.png", o});
  const auto& row = report.at("results")[0];
  double expected = 0;
  for (const auto& f : s.videos[0]) expected += fake_pyiqa_score("musiq", f) / 3;
  CHECK(std::abs(row.at("musiq").get<double>() - expected) <= 1e-6 * expected);
  CHECK(row.at("per_frame").at("dists").size() == 2);
  const std::string impl = report.at("metrics_info").at("musiq").at("impl").get<std::string>();
  CHECK(impl.find("pyiqa bridge: python3") == 0);
  CHECK(has(impl, ", pyiqa musiq (lower_better False, score range ~0, ~100) {\"pyiqa\":\"0.0-fake\""));
  CHECK(!has(impl, "dists"));  // only its own key's line
  CHECK(has(report.at("metrics_info").at("dino_score").at("convention").get<std::string>(), "mean over pairs"));
  CHECK(has(row.at("content_lpips").at("unavailable").get<std::string>(), "--metric-weights"));
  fs::remove_all(s.root);
}

TEST_CASE("each pyiqa failure makes only the affected keys unavailable, with the reason") {
  const BridgeScene s = make_bridge_scene("pyiqa_failures");
  {
    const FakePyiqa fake("absent");
    const auto o = b::run_bridge(s.options, s.seqs);
    for (const char* key : {"clipiqa_plus", "musiq", "qalign", "musiq_paq2piq", "dists", "ckdn"})
      CHECK_MESSAGE(has(reason(o, "seq1", key), "cannot import pyiqa in "), key);
    CHECK(has(reason(o, "seq1", "musiq"), "No module named 'torch'"));
  }
  {
    const FakePyiqa fake("no_weights=musiq");
    const auto o = b::run_bridge(s.options, s.seqs);
    CHECK(has(reason(o, "seq0", "musiq"), "RuntimeError: cannot download the weights of musiq"));
    CHECK(o.values.at("seq0").count("musiq_paq2piq") == 1);  // the other keys still score
  }
  {
    const FakePyiqa fake("unreadable=video0/f2");
    const auto o = b::run_bridge(s.options, s.seqs);
    CHECK(has(reason(o, "seq0", "ckdn"), "OSError: fake pyiqa ckdn: cannot read"));
    CHECK(o.values.at("seq1").count("ckdn") == 1);  // the other sequence keeps its values
  }
  {
    const FakePyiqa fake("out_of_range=clipiqa+");
    const auto o = b::run_bridge(s.options, s.seqs);
    for (const char* seq : {"seq0", "seq1"}) CHECK(has(reason(o, seq, "clipiqa_plus"), "outside its declared range 0, 1"));
    CHECK(o.values.at("seq0").count("qalign") == 1);
  }
  {
    const FakePyiqa fake("flip=dists");
    const auto o = b::run_bridge(s.options, s.seqs);
    CHECK(has(reason(o, "seq0", "dists"), "pyiqa dists has lower_better=False; Style4D-Bench's dists is lower-is-better"));
  }
  fs::remove_all(s.root);
}

TEST_CASE("a broken bridge process makes every key asked for unavailable with the reason") {
  const BridgeScene s = make_bridge_scene("process_failures");
  const auto with_script = [&](const char* name, const char* text) {
    b::BridgeOptions o = s.options;
    o.script = s.root / name;
    std::ofstream(*o.script) << text;
    return b::run_bridge(o, s.seqs);
  };
  const auto crash = with_script("crash.py", "import sys\nsys.stderr.write('bridge: boom\\n')\nsys.exit(3)\n");
  CHECK(crash.values.empty());
  CHECK(has(reason(crash, "seq1", "qalign"), "exited with code 3"));
  CHECK(has(reason(crash, "seq1", "qalign"), "bridge: boom"));
  const auto garbage = with_script("garbage.py", "import json, sys\nr = json.load(open(sys.argv[1]))\n"
                                                 "open(r['output'], 'w').write('{not json')\n");
  CHECK(has(reason(garbage, "seq0", "ckdn"), "is not valid JSON"));
  const auto short_list = with_script("short.py",
                                      "import json, sys\nr = json.load(open(sys.argv[1]))\n"
                                      "res = {q['id']: {'clipiqa_plus': [0.5] * (len(q['frames']) - 1)} for q in r['sequences']}\n"
                                      "json.dump({'protocol': r['protocol'], 'results': res}, open(r['output'], 'w'))\n");
  CHECK(has(reason(short_list, "seq0", "clipiqa_plus"), "holds 2 values for 3 frames, expected 3"));
  b::BridgeOptions missing = s.options;
  missing.python = s.root / "no-such-python";
  CHECK(has(reason(b::run_bridge(missing, s.seqs), "seq1", "dists"), "cannot start"));
  // A 1-frame sequence gets no pair values: unavailable, not a made-up 0.
  const FakePyiqa fake;
  b::BridgeSequence one = s.seqs[0];
  one.frames.resize(1);
  one.metrics = {"dists", "musiq"};
  const auto o = b::run_bridge(s.options, {one});
  CHECK(reason(o, "seq0", "dists") == "needs at least 2 frames");
  CHECK(reason(o, "seq0", "musiq") == "(no reason)");
  fs::remove_all(s.root);
}

TEST_CASE("dino_score: VBench's subject consistency through torch.hub, on a fake DINO of channel means") {
  // torch comes from the system Python (python3-torch); without it there is nothing to run.
  if (std::system((std::string(S4D_TEST_PYTHON) + " -c 'import torch, torchvision' 2>/dev/null").c_str()) != 0) {
    MESSAGE("skipped: " S4D_TEST_PYTHON " cannot import torch and torchvision (tools/run-tests.sh installs them)");
    return;
  }
  const fs::path root = fs::temp_directory_path() / numbered("s4d_bridge_dino_", int(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "frames");
  // 230x224: the bridge's shorter-side-224 resize keeps the size. Red, greyish, then blue frames: after
  // ImageNet normalisation the blue one points away from the red one (cos -0.82, clipped to 0) but not
  // from the grey one (cos 0.05).
  const float colours[3][3] = {{0.9f, 0.2f, 0.2f}, {0.6f, 0.45f, 0.5f}, {0.1f, 0.5f, 0.9f}};
  b::BridgeSequence seq{"seq0", {}, "", {"dino_score"}};
  std::vector<std::array<double, 3>> f;  // unit "CLS features": per-channel means of the normalised frame
  for (int t = 0; t < 3; ++t) {
    seq.frames.push_back(root / "frames" / numbered("f", t).append(".png"));
    s4d::io::write_png(seq.frames.back(), s4d::test::constant_image(230, 224, colours[t][0], colours[t][1], colours[t][2]));
    const s4d::io::ImageF im = s4d::io::read_png(seq.frames.back());
    const double mean[3] = {0.485, 0.456, 0.406}, std[3] = {0.229, 0.224, 0.225};
    std::array<double, 3> v{};
    double norm = 0;
    for (int c = 0; c < 3; ++c) {
      v[c] = (s4d::test::channel_mean(im, c) - mean[c]) / std[c];
      norm += v[c] * v[c];
    }
    for (double& x : v) x /= std::sqrt(norm);
    f.push_back(v);
  }
  const auto cos = [&](size_t i, size_t j) { return f[i][0] * f[j][0] + f[i][1] * f[j][1] + f[i][2] * f[j][2]; };
  const s4d::test::ScopedEnv repo("S4D_DINO_REPO", (fs::path(S4D_SOURCE_DIR) / "tests" / "bench" / "fake_dino").string());
  const auto out = b::run_bridge({S4D_TEST_PYTHON, std::nullopt, root / "bridge", {"dino_score"}}, {seq});
  REQUIRE_MESSAGE(out.errors.empty(), reason(out, "seq0", "dino_score"));
  const std::vector<double>& s = out.values.at("seq0").at("dino_score");
  REQUIRE(s.size() == 2);
  CHECK((cos(0, 2) < 0 && cos(1, 2) > 0));  // s_2 has a clipped and an unclipped term
  // s_i = (max(0, cos(f_i-1, f_i)) + max(0, cos(f_0, f_i))) / 2; float32 features in torch against
  // double here: measured 2.5e-7 absolute.
  for (size_t i = 1; i < 3; ++i) {
    const double expected = (std::max(0.0, cos(i - 1, i)) + std::max(0.0, cos(0, i))) / 2;
    CHECK(std::abs(s[i - 1] - expected) < 1e-6);
  }
  fs::remove_all(root);
}

TEST_CASE("the embedded bridge script is tools/pyiqa_bridge.py") {
  std::ifstream f(fs::path(S4D_SOURCE_DIR) / "tools" / "pyiqa_bridge.py");
  std::stringstream text;
  text << f.rdbuf();
  REQUIRE(!text.str().empty());
  CHECK(b::embedded_bridge_script() == text.str());
}
