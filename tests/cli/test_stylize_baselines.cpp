// The paper's baselines 4DGS(AdaIN) and 4DGS(AdaAttN) end to end (`style4d stylize --stylizer
// adain|adaattn --method scratch`) on a tiny run of the built-in scene (3 cameras, 3 frames, 32x24,
// 20 + 20 iterations; the scratch runs retrain with 12 + 20), with random weights at the published
// networks' shapes written as the safetensors files the stylizers read. Each must leave a scratch run
// whose style file names its Gaussian count, renders that differ from the original scene, and stage-3
// frames equal to what `stylize-frames` gives with the same stylizer, weights, style and frames.
// Then bench/paper_tables.sh on the same run (keeping those two styles: the same names and options)
// with random AdaIN, AdaAttN and HGST weights: every row of both tables filled, and a row for weights
// that are not there marked skipped.
#include <doctest/doctest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <cmath>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>

#include "cli_run.h"
#include "nn_fixture.h"
#include "run4d_fixture.h"
#include "s4d/io/image_io.h"
#include "s4d/run/style_file.h"
#include "style_fixture.h"

namespace fs = std::filesystem;

namespace {

using s4d::test::read_text;
using s4d::test::run_style4d;

struct TinyRun {
  fs::path dir, data, run;
};

const TinyRun& tiny_run() {
  static const TinyRun r = [] {
    const fs::path dir = s4d::test::fresh_dir("stylize_baselines");
    TinyRun out{dir, dir / "data", dir / "run"};
    REQUIRE(run_style4d("synth", "--out " + out.data.string() + " --cams 3 --frames 3 --size 32x24", dir / "synth.log") == 0);
    REQUIRE_MESSAGE(run_style4d("train", "--data " + out.data.string() + " --out " + out.run.string() +
                                             " --preset fast --iters 20 --fine-iters 20 --batch 1",
                                dir / "train.log") == 0,
                    read_text(dir / "train.log"));
    return out;
  }();
  return r;
}

// Random weights of `stylizer` (adain, adaattn, hgst) at the published widths in a fresh folder. The last layer's biases
// are raised by 0.5 so that the decoded frames sit inside [0, 1] rather than clamped flat.
fs::path write_weights(const std::string& stylizer) {
  const fs::path dir = tiny_run().dir / ("weights_" + stylizer);
  fs::create_directories(dir);
  std::mt19937 rng(41);
  if (stylizer == "adain" || stylizer == "hgst") {
    s4d::test::NetParams decoder = s4d::test::random_decoder({}, rng);
    for (float& b : decoder.at("28").bias) b += 0.5f;
    s4d::test::write_params(dir / "vgg_normalised.safetensors", s4d::test::random_vgg({}, 4, rng));
    s4d::test::write_params(dir / "decoder.safetensors", decoder);
    if (stylizer == "hgst") s4d::test::write_params(dir / "mcc_module.safetensors", s4d::test::random_mcc({}, rng));
  } else {
    s4d::test::AdaattnParams p = s4d::test::random_adaattn({}, rng);
    for (float& b : p.decoder.at("decoder_layer_2.24").bias) b += 0.5f;
    s4d::test::write_adaattn(dir, p);
  }
  return dir;
}

// The test camera's middle frame rendered from the run, in `style` ("" for the original scene).
s4d::io::ImageF render_middle(const std::string& style) {
  const TinyRun& r = tiny_run();
  const fs::path out = r.dir / ("render_" + (style.empty() ? std::string("original") : style));
  fs::remove_all(out);
  const std::string style_arg = style.empty() ? "" : " --style " + style;
  REQUIRE_MESSAGE(run_style4d("render", "--run " + r.run.string() + style_arg + " --path test --format png --out " + out.string(),
                              out.string() + ".log") == 0,
                  read_text(out.string() + ".log"));
  return s4d::io::read_png(out / "cam00" / "0001.png");
}

void check_baseline(const std::string& stylizer) {
  CAPTURE(stylizer);
  const TinyRun& r = tiny_run();
  const fs::path weights = write_weights(stylizer);
  const std::string name = "4dgs_" + stylizer;  // bench/paper_tables.sh's name: its test below reuses the style
  const std::string network = " --stylizer " + stylizer + " --weights " + weights.string() + " --style-size 32";
  const fs::path log = r.dir / (name + ".log");
  REQUIRE_MESSAGE(run_style4d("stylize", "--run " + r.run.string() + " --style " + s4d::test::kBuiltinStyle + " --name " + name +
                                             network + " --method scratch --iters 12 --spiral-frames 2",
                              log) == 0,
                  read_text(log));
  const fs::path dir = r.run / "style" / name;

  // A scratch run trained on the stylized frames, and a style file that names it.
  const nlohmann::json summary = nlohmann::json::parse(read_text(dir / "stylize.json"));
  CHECK(summary.at("stylizer") == stylizer);
  CHECK(summary.at("method") == "scratch");
  const nlohmann::json scratch = nlohmann::json::parse(read_text(dir / "run" / "train.json"));
  CHECK(scratch.at("complete") == true);
  // --iters sets the retraining's length (the run's stage 1 trained 20), the rest of its settings are the run's.
  const nlohmann::json original = nlohmann::json::parse(read_text(r.run / "train.json"));
  CHECK(scratch.at("settings").at("iterations") == 12);
  CHECK(original.at("settings").at("iterations") == 20);
  CHECK(scratch.at("settings").at("fine_iterations") == original.at("settings").at("fine_iterations"));
  const s4d::run::StyleFile file = s4d::run::read_style_file(s4d::run::style_file_path(r.run, name));
  CHECK(file.method == s4d::run::StyleMethod::scratch);
  CHECK(file.count == scratch.at("num_gaussians").get<uint32_t>());
  CHECK(file.settings.at("stylizer") == stylizer);

  // Its renders are not the original scene's: the worst pixel of the test camera's middle frame
  // moves by far more than 8-bit rounding (measured: adain 0.48, adaattn 0.67).
  CHECK(s4d::test::max_abs_diff(render_middle(name), render_middle("")) > 0.1f);

  // Stage 3's frames of camera 0 are the stylizer's on the same frames (seed 0 and strength 1 are
  // both commands' defaults), and not the content. Both are 8-bit PNGs of the same float frames from
  // the same kernels: measured worst difference 0 (one level allowed for lavapipe's thread count).
  const fs::path frames = r.dir / (name + "_frames");
  const fs::path frames_log = r.dir / (name + "_frames.log");
  REQUIRE_MESSAGE(run_style4d("stylize-frames", "--in " + (r.data / "cam00").string() + " --style " + s4d::test::kBuiltinStyle +
                                                    network + " --out " + frames.string(),
                              frames_log) == 0,
                  read_text(frames_log));
  for (int k = 0; k < 3; ++k) {
    CAPTURE(k);
    const s4d::io::ImageF stage3 = s4d::io::read_png(dir / "stylized" / "cam00" / s4d::test::png_name("000", k));
    const s4d::io::ImageF direct = s4d::io::read_png(frames / s4d::test::png_name("000", k));
    CHECK(s4d::test::max_abs_diff(stage3, direct) <= 1.0f / 255);
    CHECK(s4d::test::max_abs_diff(stage3, s4d::io::read_png(r.data / "cam00" / s4d::test::png_name("000", k))) > 0.1f);
  }
}

}  // namespace

TEST_CASE("4DGS(AdaIN): stylize --stylizer adain --method scratch trains a 4DGS run on the AdaIN frames") {
  check_baseline("adain");
}

TEST_CASE("4DGS(AdaAttN): stylize --stylizer adaattn --method scratch trains a 4DGS run on the AdaAttN frames") {
  check_baseline("adaattn");
}

namespace {

// bench/paper_tables.sh OUT --run RUN ARGS on the tiny run, short; returns its paper_tables.json.
nlohmann::json paper_tables(const fs::path& out, const std::string& args) {
  const TinyRun& r = tiny_run();
  const std::string cmd = "S4D_EXE=" + std::string(S4D_STYLE4D_EXE) + " " + S4D_SOURCE_DIR + "/bench/paper_tables.sh " +
                          out.string() + " --run " + r.run.string() + " --iters 10 --mlp-iters 5 --spiral-frames 2 --style-size 32 " +
                          args + " > " + out.string() + ".log 2>&1";
  REQUIRE_MESSAGE(std::system(cmd.c_str()) == 0, read_text(out.string() + ".log"));
  return nlohmann::json::parse(read_text(out / "paper_tables.json"));
}

const nlohmann::json& row(const nlohmann::json& tables, const std::string& name) {
  for (const nlohmann::json& r : tables.at("comparison"))
    if (r.at("name") == name) return r;
  FAIL("no row " << name);
  throw std::logic_error("unreachable");
}

}  // namespace

TEST_CASE("bench/paper_tables.sh fills both tables on a tiny run and marks a method without weights as skipped") {
  const TinyRun& r = tiny_run();
  const fs::path out = r.dir / "tables";
  const nlohmann::json tables = paper_tables(out, "--adain-weights " + write_weights("adain").string() + " --adaattn-weights " +
                                                      write_weights("adaattn").string() + " --hgst-weights " +
                                                      write_weights("hgst").string());
  for (const char* name : {"4dgs_adain", "4dgs_adaattn", "style4d_patch", "style4d_hgst", "ablation_no_mlp", "ablation_scratch"}) {
    CAPTURE(name);
    const nlohmann::json& m = row(tables, name);
    CHECK(m.at("status") == "ok");
    // Scored by style4d bench: the weight-free metrics are numbers, the learned ones unavailable.
    CHECK(m.at("bench").at("uiqm").is_number());
    CHECK(m.at("bench").at("warp_loss").is_number());
    CHECK(m.at("bench").at("content_ssim").is_number());
    CHECK(m.at("bench").at("dists").contains("unavailable"));
    CHECK(m.at("test_psnr_vs_stylized").is_number());
  }
  CHECK(row(tables, "4dgs_adain").at("method") == "scratch");
  CHECK(row(tables, "style4d_hgst").at("stylizer") == "hgst");
  CHECK(row(tables, "ablation_no_mlp").at("method") == "colors");
  // Style Gaussians on the original frames against the run's own test PSNR.
  const nlohmann::json& recon = tables.at("reconstruction");
  CHECK(recon.at("4dgs_test_psnr") == nlohmann::json::parse(read_text(r.run / "train.json")).at("test_psnr"));
  CHECK(recon.at("style_gaussians").at("status") == "ok");
  // 10 steps from the run's own look (zero deltas, MLPs that add nothing) against the same test
  // frames: measured +0.05 dB.
  CHECK(std::abs(recon.at("style_gaussians").at("test_psnr_vs_stylized").get<double>() - recon.at("4dgs_test_psnr").get<double>()) < 1.0);
  const std::string md = read_text(out / "paper_tables.md");
  CHECK(md.find("| 4DGS(AdaAttN) | ok |") != std::string::npos);
  CHECK(md.find("Style Gaussians vs 4DGS on the original frames") != std::string::npos);

  // Again without HGST's weights: that row is skipped, naming the file; the others are kept.
  const fs::path none = r.dir / "no_weights";
  const nlohmann::json again = paper_tables(out, "--adain-weights " + write_weights("adain").string() + " --adaattn-weights " +
                                                     write_weights("adaattn").string() + " --hgst-weights " + none.string());
  CHECK(row(again, "style4d_hgst").at("status") == "skipped: no weights at " + (none / "vgg_normalised.safetensors").string());
  CHECK(row(again, "4dgs_adain").at("status") == "ok");
  CHECK(read_text(out / "paper_tables.md").find("skipped: no weights at") != std::string::npos);
}
