// style4d bench --run on the shared 4DGS run (run4d_fixture.h) with a style trained as
// test_stylize_command.cpp trains it: both protocols rendered for the original scene and the style,
// the report's key contract (every METRICS.md key a number or {"unavailable": why}, each weight-free
// one from its protocol), the pyiqa bridge against a fake pyiqa (fake_pyiqa.h) on each
// protocol, the report files, the merge of reports, and the refusals.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "s4d/io/image_io.h"

#include "../bench/fake_pyiqa.h"
#include "run4d_fixture.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

const std::string kStyle = std::string(S4D_SOURCE_DIR) + "/assets/styles/builtin.png";
const char* const kKeys[] = {"uiqm", "clipiqa_plus", "musiq", "qalign", "musiq_paq2piq", "dists", "warp_loss",
                             "dino_score", "ckdn", "style_lpips", "content_ssim", "content_lpips", "style_loss_gram", "psnr"};

// The .png frames of a folder in name order (as the bench reads them).
std::vector<io::ImageF> frames_in(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".png") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<io::ImageF> out;
  for (const fs::path& f : files) out.push_back(io::read_png(f));
  return out;
}

// The test protocol's camera folders under `dir` (renders/<method>/test), in name order.
std::vector<std::string> camera_dirs(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory()) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// Mean over every test-camera frame of f(frame, camera, index): the bench pools frames of all cameras.
template <class F>
double mean_over_test_frames(const fs::path& test_dir, F f) {
  double sum = 0;
  int n = 0;
  for (const std::string& cam : camera_dirs(test_dir)) {
    const std::vector<io::ImageF> frames = frames_in(test_dir / cam);
    for (size_t k = 0; k < frames.size(); ++k, ++n) sum += f(frames[k], cam, k);
  }
  REQUIRE(n > 0);
  return sum / n;
}

// The style "full" with test_stylize_command.cpp's settings: trained once, reused by the other file.
void train_style() {
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "bench_stylize.log";
  REQUIRE_MESSAGE(test::run_style4d("stylize", "--run " + r.run.string() + " --style " + kStyle +
                                                   " --name full --iters 60 --mlp-iters 20 --spiral-frames 4", log) == 0,
                  test::read_text(log));
}

}  // namespace

TEST_CASE("bench --run renders both protocols for the original scene and a style and writes the report") {
  train_style();
  const test::Run4d& r = test::run4d();
  const fs::path out = r.root / "bench_run";
  fs::remove_all(out);
  const fs::path log = r.root / "bench_run.log";
  const test::FakePyiqa fake;  // the embedded bridge script against the fake pyiqa
  REQUIRE_MESSAGE(test::run_style4d("bench", "--run " + r.run.string() + " --style full --style original --spiral-frames 4 --out " +
                                                 out.string() + " --python python3 --bridge-metrics musiq,dists,ckdn",
                                    log) == 0,
                  test::read_text(log));
  for (const char* f : {"report.json", "report.md", "report.csv", "contact_sheet.png", "plots/warp_loss.png", "plots/uiqm.png",
                        "renders/original/spiral/0003.png", "renders/original/spiral/flow/fw_0002.exr",
                        "renders/full/spiral/0003.png", "renders/full/test/frames.json", "renders/original/test/frames.json"})
    CHECK_MESSAGE(fs::exists(out / f), f);
  const nlohmann::json j = nlohmann::json::parse(test::read_text(out / "report.json"));
  CHECK(j.at("mode") == "run");
  CHECK(j.at("metrics_info").at("warp_loss").at("protocol") == "spiral");
  CHECK(j.at("metrics_info").at("content_ssim").at("protocol") == "test");
  REQUIRE(j.at("results").size() == 2);
  const nlohmann::json &full = j.at("results")[0], &original = j.at("results")[1];
  CHECK(full.at("method") == "full");
  CHECK(full.at("style") == "builtin");  // the style image request.json names
  CHECK(original.at("method") == "original");
  for (const nlohmann::json* m : {&full, &original}) {
    for (const char* k : kKeys) {
      const nlohmann::json& v = m->at(k);
      CHECK_MESSAGE((v.is_number() || !v.at("unavailable").get<std::string>().empty()), k);
    }
    for (const char* k : {"uiqm", "content_ssim", "warp_loss"}) CHECK_MESSAGE(m->at(k).is_number(), k);
    CHECK(m->at("protocols").at("spiral").at("frames") == 4);
    CHECK(m->at("protocols").at("test").at("frames").get<int>() >= 3);  // each test camera over the 3 times
    CHECK(m->at("warp_loss") == m->at("protocols").at("spiral").at("warp_loss"));
    CHECK(m->at("uiqm") == m->at("protocols").at("test").at("uiqm"));
    CHECK(m->at("protocols").at("spiral").at("psnr").contains("unavailable"));
  }
  // The original scored against itself; the style changes the content.
  CHECK(original.at("content_ssim").get<double>() == doctest::Approx(1.0));
  CHECK(full.at("content_ssim").get<double>() < 0.99);
  // psnr is the original render's against the captured frames, recomputed here from the files the bench
  // wrote (10 log10(1 / MSE) over pixels and channels, mean over every test frame); the same 8-bit
  // frames and double sums, so only summation order differs (1e-9 dB). The style's row has none of
  // its own: it says so instead of repeating the original's.
  const double psnr = mean_over_test_frames(out / "renders" / "original" / "test", [&](const io::ImageF& im, const std::string& cam,
                                                                                      size_t k) {
    const io::ImageF truth = frames_in(out / "renders" / "ground_truth" / "test" / cam).at(k);
    REQUIRE(truth.data.size() == im.data.size());
    double se = 0;
    for (size_t i = 0; i < im.data.size(); ++i) se += (double(im.data[i]) - truth.data[i]) * (double(im.data[i]) - truth.data[i]);
    return -10.0 * std::log10(se / double(im.data.size()));
  });
  CHECK(original.at("psnr").get<double>() == doctest::Approx(psnr).epsilon(1e-9));
  CHECK(original.at("psnr").get<double>() > 15.0);  // the fixture's 160-iteration fit; a blank render scores about 10
  for (const nlohmann::json& v : {full.at("psnr"), full.at("protocols").at("test").at("psnr")})
    CHECK(v.at("unavailable").get<std::string>().find("per run, not per style") == 0);
  const std::string md = test::read_text(out / "report.md");
  CHECK(md.find("PSNR (original scene, per run)") != std::string::npos);
  const size_t row = md.find("| full |");
  REQUIRE(row != std::string::npos);
  const std::string line = md.substr(row, md.find('\n', row) - row);
  CHECK(line.substr(line.size() - 5) == "| - |");  // psnr, the last column
  CHECK(test::read_text(out / "report.md").find("| full |") != std::string::npos);
  // The bridge (fake pyiqa: musiq is 100 x each frame's red mean): musiq and ckdn from the test
  // cameras' videos, dists from the spiral; the original has no style image, so no ckdn.
  for (const nlohmann::json* m : {&full, &original}) {
    // The fake's musiq recomputed from the rendered test frames (pooled over cameras); both decode the
    // same 8-bit PNGs: at worst 4.5e-8 relative apart in test_pyiqa_bridge.
    const double musiq = mean_over_test_frames(out / "renders" / m->at("method").get<std::string>() / "test",
                                               [](const io::ImageF& im, const std::string&, size_t) {
                                                 return test::fake_pyiqa_score("musiq", im);
                                               });
    CHECK(m->at("musiq").get<double>() == doctest::Approx(musiq).epsilon(1e-6));
    CHECK(m->at("per_frame").at("musiq").size() == m->at("protocols").at("test").at("frames"));
    CHECK(m->at("per_frame").at("dists").size() == 3);  // the 4-frame spiral's pairs
    CHECK(m->at("dists") == m->at("protocols").at("spiral").at("dists"));
  }
  CHECK(full.at("ckdn").is_number());
  CHECK(original.at("ckdn").at("unavailable").get<std::string>().find("no style image") != std::string::npos);
  CHECK(j.at("metrics_info").at("musiq").at("impl").get<std::string>().find("pyiqa bridge") == 0);
  CHECK(j.at("metrics_info").at("dists").at("protocol") == "spiral");

  // A sweep's merge step over this job's report: one table, rows tagged with their source.
  const fs::path merged = r.root / "bench_merged";
  fs::remove_all(merged);
  REQUIRE_MESSAGE(test::run_style4d("bench", "--merge " + out.string() + " --out " + merged.string(), log) == 0, test::read_text(log));
  const nlohmann::json m = nlohmann::json::parse(test::read_text(merged / "report.json"));
  CHECK(m.at("mode") == "merge");
  CHECK(m.at("results").size() == 2);
  CHECK(m.at("results")[0].at("source") == (out / "report.json").string());
  CHECK(fs::exists(merged / "report.csv"));
  CHECK(test::run_style4d("bench", "--merge " + out.string() + " " + out.string() + " --out " + merged.string(), log) != 0);
  CHECK(test::read_text(log).find("already in") != std::string::npos);
}

TEST_CASE("bench --run refuses a style the run lacks, no --style, and frames-mode options, naming them") {
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "bench_refused.log", out = r.root / "bench_refused";
  CHECK(test::run_style4d("bench", "--run " + r.run.string() + " --style nosuch --out " + out.string(), log) != 0);
  CHECK(test::read_text(log).find("no style nosuch") != std::string::npos);
  CHECK(test::run_style4d("bench", "--run " + r.run.string() + " --out " + out.string(), log) != 0);
  CHECK(test::read_text(log).find("--style") != std::string::npos);
  CHECK(test::run_style4d("bench", "--run " + r.run.string() + " --style original --original x --out " + out.string(), log) != 0);
  CHECK(test::read_text(log).find("--original belongs to the frames mode (--stylized)") != std::string::npos);
  CHECK(test::run_style4d("bench", "--run " + r.run.string() + " --style original --spiral-frames 1 --out " + out.string(), log) != 0);
  CHECK(test::read_text(log).find("--spiral-frames") != std::string::npos);
  CHECK(!fs::exists(out / "report.json"));
}
