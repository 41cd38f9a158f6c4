// `style4d render --run` end to end: a run made here (the synthetic dataset from `style4d synth`, its
// point cloud written as RUN/geometry/gaussians.ply with a minimal run.json) rendered along every
// path and format, the exact flow read back by `style4d bench --flow exact`, the errors, and
// export-ply of a static run.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "s4d/data/dataset.h"
#include "s4d/io/image_io.h"
#include "s4d/io/ply_gaussians.h"

#include "cli_run.h"

namespace fs = std::filesystem;
using s4d::test::fresh_dir;
using s4d::test::read_text;
using s4d::test::run_style4d;

namespace {

constexpr double kC0 = 0.28209479177387814;

// A scratch folder with DATA (synthetic, 4 cameras x 3 frames, 48x36) and RUN (one small opaque
// Gaussian per point of DATA's point cloud, in its colour).
struct Fixture {
  fs::path root = fresh_dir("render_run");
  fs::path data = root / "data", run = root / "run";
  Fixture() {
    REQUIRE(run_style4d("synth", "--out " + data.string() + " --cams 4 --frames 3 --size 48x36", root / "synth.log") == 0);
    const s4d::data::Dataset d = s4d::data::load_dataset(data);
    REQUIRE(!d.points.empty());
    s4d::io::GaussianCloud cloud;
    for (size_t i = 0; i < d.points.size() / 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        cloud.means.push_back(d.points[3 * i + k]);
        cloud.log_scales.push_back(std::log(0.05f));
        cloud.sh.push_back(static_cast<float>((d.colors[3 * i + k] - 0.5) / kC0));
      }
      cloud.quats.insert(cloud.quats.end(), {1, 0, 0, 0});
      cloud.opacity_logits.push_back(3.0f);
    }
    fs::create_directories(run / "geometry");
    s4d::io::write_ply_gaussians(run / "geometry" / "gaussians.ply", cloud);
    std::ofstream(run / "run.json") << nlohmann::json{{"data", data.string()}, {"stage", "static"}, {"settings", nlohmann::json::object()}}.dump();
  }
  int render(const std::string& args, const fs::path& log) const {
    return run_style4d("render", "--run " + run.string() + " " + args, log);
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(read_text(p)); }

}  // namespace

TEST_CASE("render --path test writes each test camera's frames at the test times") {
  const Fixture& f = fixture();
  const fs::path out = f.root / "test_png";
  REQUIRE_MESSAGE(f.render("--path test --out " + out.string(), f.root / "test.log") == 0, read_text(f.root / "test.log"));
  for (const char* name : {"0000.png", "0001.png", "0002.png"}) {
    const s4d::io::ImageF img = s4d::io::read_png(out / "cam00" / name);
    CHECK(img.width == 48);
    CHECK(img.height == 36);
  }
  CHECK_FALSE(fs::exists(out / "cam00" / "0003.png"));
  const nlohmann::json frames = read_json(out / "frames.json");
  REQUIRE(frames["sequences"].size() == 1);
  CHECK(frames["sequences"][0]["dir"] == "cam00");
  CHECK(frames["sequences"][0]["frames"][2]["time"].get<double>() == doctest::Approx(1.0));
  CHECK(frames["sequences"][0]["frames"][1]["file"] == "0001.png");
  const nlohmann::json summary = read_json(out / "render.json");
  CHECK(summary["frames"] == 3);
  CHECK(summary["path"] == "test");
}

TEST_CASE("render --path spiral --format exr --flow writes frames and forward/backward flow per pair") {
  const Fixture& f = fixture();
  const fs::path out = f.root / "spiral_exr";
  REQUIRE_MESSAGE(f.render("--path spiral --spiral-frames 4 --format exr --flow --out " + out.string(), f.root / "spiral.log") == 0,
                  read_text(f.root / "spiral.log"));
  for (const char* name : {"0000.exr", "0003.exr"}) {
    const s4d::io::ExrImage exr = s4d::io::read_exr(out / name);
    for (const char* c : {"R", "G", "B", "A", "Z"}) CHECK_MESSAGE(exr.channels.count(c) == 1, c);
  }
  double largest = 0;
  for (int pair = 0; pair < 3; ++pair)
    for (const char* dir : {"fw", "bw"}) {
      const fs::path file = out / "flow" / (std::string(dir) + "_000" + std::to_string(pair) + ".exr");
      const s4d::io::ExrImage exr = s4d::io::read_exr(file);
      REQUIRE_MESSAGE(exr.channels.size() == 2, file);
      CHECK(exr.width == 48);
      for (float u : exr.channels.at("u")) largest = std::max(largest, double(std::abs(u)));
    }
  CHECK_FALSE(fs::exists(out / "flow" / "fw_0003.exr"));
  CHECK(largest > 0.5);  // the spiral moves the camera by pixels per frame
  const nlohmann::json frames = read_json(out / "frames.json");
  CHECK(frames["sequences"][0]["flow"] == true);
  CHECK(frames["sequences"][0]["frames"].size() == 4);
  CHECK(frames["sequences"][0]["frames"][3]["time"].get<double>() == doctest::Approx(1.0));
}

TEST_CASE("render --path train:CAM --format mp4 writes one video; bench reads the exact flow of a png spiral") {
  const Fixture& f = fixture();
  const fs::path mp4 = f.root / "train_mp4";
  REQUIRE_MESSAGE(f.render("--path train:cam01 --format mp4 --out " + mp4.string(), f.root / "mp4.log") == 0,
                  read_text(f.root / "mp4.log"));
  CHECK(fs::file_size(mp4 / "video.mp4") > 0);
  CHECK(read_json(mp4 / "frames.json")["sequences"][0]["video"] == "video.mp4");

  const fs::path png = f.root / "spiral_png", report = f.root / "report";
  REQUIRE(f.render("--path spiral --spiral-frames 3 --flow --out " + png.string(), f.root / "png.log") == 0);
  const std::string bench = "--stylized " + png.string() + " --original " + png.string() + " --style-image " +
                            (png / "0000.png").string() + " --flow exact --flow-dir " + (png / "flow").string() +
                            " --out " + report.string();
  REQUIRE_MESSAGE(run_style4d("bench", bench, f.root / "bench.log") == 0, read_text(f.root / "bench.log"));
  CHECK(read_text(report / "report.json").find("the renderer's exact flow") != std::string::npos);
  CHECK(read_text(report / "report.json").find("\"flow_dir\": \"" + (png / "flow").string() + "\"") != std::string::npos);
}

TEST_CASE("render --run errors name the file, the path or the camera, and write nothing") {
  const Fixture& f = fixture();
  const fs::path out = f.root / "never";
  const fs::path log = f.root / "error.log";
  auto fails_with = [&](const std::string& args, const std::string& message) {
    CHECK(f.render(args + " --out " + out.string(), log) != 0);
    const std::string text = read_text(log);
    CHECK_MESSAGE(text.find(message) != std::string::npos, args << " -> " << text);
    CHECK_FALSE(fs::exists(out));
  };
  fails_with("--path orbit", "expected test, spiral, train:CAM (a training camera name such as train:cam01) or a camera path FILE.json");
  fails_with("--path train:cam00", "no training camera named 'cam00'");
  fails_with("--path train:cam7", "the training cameras are cam01, cam02, cam03");
  fails_with("--path test --style ink", "no style ink in");
  fails_with("--path test --spiral-frames 5", "--spiral-frames sets the spiral's length");
  fails_with("--path test --format gif", "expected png, exr or mp4");
  fails_with("--path spiral --spiral-frames 0", "at least 1");

  const fs::path empty_run = f.root / "empty_run";
  fs::create_directories(empty_run);
  CHECK(run_style4d("render", "--run " + empty_run.string() + " --path test --out " + out.string(), log) != 0);
  CHECK(read_text(log).find((empty_run / "run.json").string() + ": missing") != std::string::npos);
  std::ofstream(empty_run / "run.json") << read_text(f.run / "run.json");
  CHECK(run_style4d("render", "--run " + empty_run.string() + " --path test --out " + out.string(), log) != 0);
  CHECK(read_text(log).find((empty_run / "geometry" / "gaussians.ply").string() + ": missing") != std::string::npos);
  CHECK_FALSE(fs::exists(out));

  fs::create_directories(out);
  std::ofstream(out / "old.png") << "x";
  CHECK(f.render("--path test --out " + out.string(), log) != 0);
  CHECK(read_text(log).find("already exists and is not an empty folder") != std::string::npos);
}

TEST_CASE("export-ply of a static run writes its Gaussians at any time") {
  const Fixture& f = fixture();
  const s4d::io::GaussianCloud stored = s4d::io::read_ply_gaussians(f.run / "geometry" / "gaussians.ply");
  for (const char* time : {"0", "0.7"}) {
    const fs::path ply = f.root / (std::string("export_") + time + ".ply");
    REQUIRE_MESSAGE(run_style4d("export-ply", "--run " + f.run.string() + " --time " + time + " --out " + ply.string(),
                                f.root / "export.log") == 0,
                    read_text(f.root / "export.log"));
    const s4d::io::GaussianCloud exported = s4d::io::read_ply_gaussians(ply);
    CHECK(exported.means == stored.means);
    CHECK(exported.log_scales == stored.log_scales);
    CHECK(exported.quats == stored.quats);
    CHECK(exported.opacity_logits == stored.opacity_logits);
    CHECK(exported.sh == stored.sh);
    CHECK(exported.sh_degree == stored.sh_degree);
  }
  CHECK(run_style4d("export-ply", "--run " + f.run.string() + " --time 2 --out " + (f.root / "x.ply").string(),
                    f.root / "export.log") != 0);
  CHECK(read_text(f.root / "export.log").find("[0, 1]") != std::string::npos);
}
