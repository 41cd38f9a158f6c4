// `style4d bench` frames mode with the learned metrics: --metric-weights (random LPIPS-VGG, DISTS
// and vgg_normalised weights the test writes, the values checked against the library on the same
// frames), --python with the bridge against a fake pyiqa (fake_pyiqa.h), the reasons reported
// without weights or with a broken interpreter, and the option errors.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "../bench/fake_pyiqa.h"
#include "cli_run.h"
#include "s4d/metrics/dists.h"
#include "s4d/metrics/gram_loss.h"
#include "s4d/metrics/lpips.h"
#include "s4d/io/image_file.h"
#include "torch_vgg_fixture.h"

namespace fs = std::filesystem;
using s4d::test::read_text;
using s4d::test::run_style4d;

namespace {

struct Frames {
  fs::path root, styl, orig, style;
  std::vector<s4d::io::ImageF> s, o;
  s4d::io::ImageF style_image;
};

// 3 random frames of 20x18 (LPIPS needs 16x16) for each video, and a 24x20 style image.
Frames make_frames(const std::string& name) {
  Frames f;
  f.root = s4d::test::fresh_dir(name);
  f.styl = f.root / "stylised", f.orig = f.root / "original", f.style = f.root / "style.png";
  fs::create_directories(f.styl);
  fs::create_directories(f.orig);
  std::mt19937 rng(41);
  for (int t = 0; t < 3; ++t) {
    const auto path = [&](const fs::path& d) { return d / (std::to_string(100 + t) + ".png"); };
    s4d::io::write_png(path(f.styl), s4d::test::random_image(20, 18, rng));
    s4d::io::write_png(path(f.orig), s4d::test::random_image(20, 18, rng));
    f.s.push_back(s4d::io::read_png(path(f.styl)));
    f.o.push_back(s4d::io::read_png(path(f.orig)));
  }
  s4d::io::write_png(f.style, s4d::test::random_image(24, 20, rng));
  f.style_image = s4d::io::read_png(f.style);
  return f;
}

nlohmann::json run_bench(const Frames& f, const std::string& extra, const std::string& tag) {
  const fs::path out = f.root / tag;
  const std::string args = "--frames " + f.styl.string() + " --name m --original " + f.orig.string() + " --style-image " +
                           f.style.string() + " --out " + out.string() + " " + extra;
  const fs::path log = f.root / (tag + ".log");
  REQUIRE_MESSAGE(run_style4d("bench", args, log) == 0, read_text(log));
  std::ifstream in(out / "report.json");
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("bench --metric-weights scores lpips, dists and the gram loss as the library does; without them they say what to supply") {
  const Frames f = make_frames("bench_learned");
  // The program loads the published widths (VGG16 64..512), so the weights are full-size random
  // ones; on 20x18 frames the passes stay small.
  std::mt19937 rng(42);
  const fs::path weights = f.root / "weights";
  fs::create_directories(weights);
  s4d::test::write_params(weights / "vgg16.safetensors", s4d::test::random_torch_vgg({}, false, rng));
  std::vector<s4d::io::NamedTensor> heads;
  const int64_t widths[5] = {64, 128, 256, 512, 512};
  for (int l = 0; l < 5; ++l)
    heads.push_back({"lin" + std::to_string(l) + ".model.1.weight", {1, widths[l], 1, 1},
                     s4d::test::random_values(size_t(widths[l]), 0.0f, 0.1f, rng)});
  s4d::io::write_safetensors(weights / "lpips_vgg.safetensors", heads);
  s4d::test::write_params(weights / "vgg_normalised.safetensors", s4d::test::random_vgg({}, 5, rng));
  const std::vector<int64_t> ab{1, 1475, 1, 1};
  s4d::io::write_safetensors(weights / "dists.safetensors", {{"alpha", ab, s4d::test::random_values(1475, 0.01f, 0.03f, rng)},
                                                             {"beta", ab, s4d::test::random_values(1475, 0.0f, 0.02f, rng)}});

  // The authors' 3DGS-style LPIPS input ([0, 1] as is), checked against the library's; the standard
  // input is the default (test_lpips covers both).
  const auto report = run_bench(f, "--metric-weights " + weights.string() + " --lpips-input 3dgs", "with");
  const auto& r = report.at("results")[0];
  const s4d::metrics::Lpips lpips(s4d::test::context(), s4d::io::SafetensorsFile(weights / "vgg16.safetensors"),
                                  s4d::io::SafetensorsFile(weights / "lpips_vgg.safetensors"), s4d::metrics::LpipsNet::vgg,
                                  std::nullopt, s4d::metrics::LpipsInput::unit);
  double content = 0;
  for (int t = 0; t < 3; ++t) content += lpips(f.s[t], f.o[t]) / 3;
  // The same kernels on the same device and frames: measured identical.
  CHECK(std::abs(r.at("content_lpips").get<double>() - content) <= 1e-9 * content);
  CHECK(r.at("per_frame").at("style_lpips").size() == 3);
  // Style LPIPS recomputed: each frame against the style image read and resized to the frame as the
  // program does (io::read_image_rgb, io::resize_image); same kernels and inputs, so equal
  // within 1e-9 relative like content_lpips above (passes at that bound).
  const s4d::io::ImageF style_at_frame = s4d::io::resize_image(s4d::io::read_image_rgb(f.style), 20, 18);
  double style = 0;
  for (int t = 0; t < 3; ++t) style += lpips(f.s[t], style_at_frame) / 3;
  CHECK(std::abs(r.at("style_lpips").get<double>() - style) <= 1e-9 * style);
  const s4d::metrics::GramStyleLoss gram(s4d::test::context(), s4d::io::SafetensorsFile(weights / "vgg_normalised.safetensors"),
                                         s4d::metrics::GramBackbone::vgg_normalised);
  const double g0 = gram(f.s[0], f.style_image);
  // The program reads the style image with io::read_image_rgb, the test with io::read_png: the same
  // values (both v / 255), so equal within 1e-9 relative like the others.
  CHECK(std::abs(r.at("per_frame").at("style_loss_gram")[0].get<double>() - g0) <= 1e-9 * g0);
  const s4d::metrics::Dists dists(s4d::test::context(), s4d::io::SafetensorsFile(weights / "vgg16.safetensors"),
                                  s4d::io::SafetensorsFile(weights / "dists.safetensors"));
  REQUIRE(r.at("per_frame").at("dists").size() == 2);  // consecutive pairs of the 3 stylised frames
  const double d1 = dists(f.s[1], f.s[0]);
  CHECK(std::abs(r.at("per_frame").at("dists")[0].get<double>() - d1) <= 1e-9 * d1);  // same kernels: measured identical
  CHECK(report.at("metrics_info").at("content_lpips").at("impl").get<std::string>().find("native LPIPS") == 0);
  CHECK(report.at("metrics_info").at("content_lpips").at("convention").get<std::string>().find("no 2x-1") != std::string::npos);
  CHECK(report.at("metrics_info").at("dists").at("impl").get<std::string>().find("native DISTS") == 0);
  CHECK(r.at("musiq").at("unavailable").get<std::string>().find("--python") != std::string::npos);

  // Without the folder: the keys say which files to supply.
  const auto none = run_bench(f, "", "none").at("results")[0];
  CHECK(none.at("content_lpips").at("unavailable").get<std::string>().find("--metric-weights DIR") != std::string::npos);
  CHECK(none.at("dino_score").at("unavailable").get<std::string>().find("dino_vitb16.safetensors") != std::string::npos);
  CHECK(none.at("clipiqa_plus").at("unavailable").get<std::string>().find("clipiqa_plus.safetensors") != std::string::npos);
  // A folder with only dists.safetensors (nothing loads: every network lacks a file): each key names
  // what its network is missing.
  const fs::path partial_dir = f.root / "partial_weights";
  fs::create_directories(partial_dir);
  fs::copy_file(weights / "dists.safetensors", partial_dir / "dists.safetensors");
  const auto partial = run_bench(f, "--metric-weights " + partial_dir.string(), "partial").at("results")[0];
  CHECK(partial.at("style_lpips").at("unavailable").get<std::string>().find("vgg16.safetensors and lpips_vgg.safetensors") !=
        std::string::npos);
  // Only the absent file is asked for; the present one is named as there.
  const std::string dists_why = partial.at("dists").at("unavailable").get<std::string>();
  CHECK(dists_why.find("add vgg16.safetensors to " + partial_dir.string() + " (--metric-weights; dists.safetensors is there)") !=
        std::string::npos);
  CHECK(partial.at("style_loss_gram").at("unavailable").get<std::string>().find("vgg_normalised.safetensors") != std::string::npos);
  CHECK(partial.at("dino_score").at("unavailable").get<std::string>().find("add dino_vitb16.safetensors to " + partial_dir.string()) !=
        std::string::npos);
  const std::string ckdn_why = partial.at("ckdn").at("unavailable").get<std::string>();
  CHECK(ckdn_why.find("add ckdn.safetensors to " + partial_dir.string()) != std::string::npos);
  CHECK(ckdn_why.find("CKDN_model_best-38b27dc6.pth") != std::string::npos);
  const std::string clipiqa_why = partial.at("clipiqa_plus").at("unavailable").get<std::string>();
  CHECK(clipiqa_why.find("add clipiqa_plus.safetensors to " + partial_dir.string()) != std::string::npos);
  CHECK(clipiqa_why.find("RN50.pt and pyiqa's CLIP-IQA+_learned_prompts-603f3273.pth") != std::string::npos);
  // A folder holding the other network's files: --lpips-net alex asks for the AlexNet files and points
  // at the VGG ones there; --gram-vgg torchvision likewise at vgg_normalised.
  const auto alex = run_bench(f, "--metric-weights " + weights.string() + " --lpips-net alex --gram-vgg torchvision", "alex")
                        .at("results")[0];
  const std::string alex_why = alex.at("content_lpips").at("unavailable").get<std::string>();
  CHECK(alex_why.find("add alexnet.safetensors and lpips_alex.safetensors to") != std::string::npos);
  CHECK(alex_why.find("or pass --lpips-net vgg to use the vgg16.safetensors and lpips_vgg.safetensors there") != std::string::npos);
  CHECK(alex.at("style_loss_gram").at("unavailable").get<std::string>().find(
            "or pass --gram-vgg normalised to use the vgg_normalised.safetensors there") != std::string::npos);
  fs::remove_all(f.root);
}

TEST_CASE("bench --python runs the bridge script; its numbers reach report.json, a failure gives the reason") {
  const Frames f = make_frames("bench_bridge");
  const s4d::test::FakePyiqa fake;  // the embedded bridge script against the fake pyiqa
  const auto report = run_bench(f, "--python python3 --bridge-metrics musiq,dists", "bridge");
  const auto& r = report.at("results")[0];
  double expected = 0;
  for (const auto& im : f.s) expected += s4d::test::fake_pyiqa_score("musiq", im) / 3;
  CHECK(std::abs(r.at("musiq").get<double>() - expected) <= 1e-6 * expected);  // measured 4.5e-8 relative at worst (test_pyiqa_bridge)
  CHECK(r.at("per_frame").at("dists").size() == 2);
  CHECK(r.at("qalign").is_object());  // not asked for
  CHECK(report.at("metrics_info").at("musiq").at("impl").get<std::string>().find("pyiqa bridge: python3") == 0);
  CHECK(fs::exists(f.root / "bridge" / "bridge" / "request.json"));

  const auto broken = run_bench(f, "--python " + (f.root / "no-python").string(), "broken").at("results")[0];
  CHECK(broken.at("ckdn").at("unavailable").get<std::string>().find("cannot start") != std::string::npos);

  const fs::path log = f.root / "bad.log";
  CHECK(run_style4d("bench", "--frames " + f.styl.string() + " --original " + f.orig.string() + " --style-image " +
                                 f.style.string() + " --out " + (f.root / "bad").string() + " --bridge-metrics nope --python python3",
                    log) != 0);
  CHECK(read_text(log).find("'nope' is not a bridge key") != std::string::npos);
  CHECK(run_style4d("bench", "--frames " + f.styl.string() + " --original " + f.orig.string() + " --style-image " +
                                 f.style.string() + " --out " + (f.root / "bad").string() + " --gram-vgg torchvision",
                    log) != 0);
  CHECK(read_text(log).find("--gram-vgg: needs --metric-weights") != std::string::npos);
  CHECK(run_style4d("bench", "--frames " + f.styl.string() + " --original " + f.orig.string() + " --style-image " +
                                 f.style.string() + " --out " + (f.root / "bad").string() + " --metric-weights " +
                                 f.root.string() + " --lpips-net squeeze",
                    log) != 0);
  CHECK(read_text(log).find("--lpips-net: expected one of vgg, alex") != std::string::npos);
  fs::remove_all(f.root);
}
