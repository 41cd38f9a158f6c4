// style4d bench --run on the shared 4DGS run (run4d_fixture.h) with a style trained as
// test_stylize_command.cpp trains it: both protocols rendered for the original scene and the style,
// the report's key contract (every METRICS.md key a number or {"unavailable": why}, each weight-free
// one from its protocol), the pyiqa bridge with a stand-in script (bridge_stand_in.h) on each
// protocol, the report files, the merge of reports, and the refusals.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <fstream>

#include "../bench/bridge_stand_in.h"
#include "run4d_fixture.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

const std::string kStyle = std::string(S4D_SOURCE_DIR) + "/assets/styles/builtin.png";
const char* const kKeys[] = {"uiqm", "clipiqa_plus", "musiq", "qalign", "musiq_paq2piq", "dists", "warp_loss",
                             "dino_score", "ckdn", "style_lpips", "content_ssim", "content_lpips", "style_loss_gram", "psnr"};

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
  const fs::path log = r.root / "bench_run.log", stand_in = r.root / "bridge_stand_in.py";
  std::ofstream(stand_in) << test::kBridgeStandIn;
  REQUIRE_MESSAGE(test::run_style4d("bench", "--run " + r.run.string() + " --style full --style original --spiral-frames 4 --out " +
                                                 out.string() + " --python python3 --bridge-script " + stand_in.string() +
                                                 " --bridge-metrics musiq,dists,ckdn",
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
    for (const char* k : {"uiqm", "content_ssim", "warp_loss", "psnr"}) CHECK_MESSAGE(m->at(k).is_number(), k);
    CHECK(m->at("protocols").at("spiral").at("frames") == 4);
    CHECK(m->at("protocols").at("test").at("frames").get<int>() >= 3);  // each test camera over the 3 times
    CHECK(m->at("warp_loss") == m->at("protocols").at("spiral").at("warp_loss"));
    CHECK(m->at("uiqm") == m->at("protocols").at("test").at("uiqm"));
    CHECK(m->at("protocols").at("spiral").at("psnr").contains("unavailable"));
  }
  // The original scored against itself; the style changes the content; psnr is the original render's.
  CHECK(original.at("content_ssim").get<double>() == doctest::Approx(1.0));
  CHECK(full.at("content_ssim").get<double>() < 0.99);
  CHECK(full.at("psnr") == original.at("psnr"));
  CHECK(original.at("psnr").get<double>() > 15.0);
  CHECK(test::read_text(out / "report.md").find("| full |") != std::string::npos);
  // The bridge (stand-in: each frame's mean value; mean |difference| of consecutive frames): musiq
  // and ckdn from the test cameras' videos, dists from the spiral; the original has no style image,
  // so no ckdn.
  for (const nlohmann::json* m : {&full, &original}) {
    CHECK(m->at("musiq").get<double>() > 0.0);
    CHECK(m->at("musiq").get<double>() < 1.0);
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
  CHECK(test::read_text(log).find("--original belongs to the --frames mode") != std::string::npos);
  CHECK(test::run_style4d("bench", "--run " + r.run.string() + " --style original --spiral-frames 1 --out " + out.string(), log) != 0);
  CHECK(test::read_text(log).find("--spiral-frames") != std::string::npos);
  CHECK(!fs::exists(out / "report.json"));
}
