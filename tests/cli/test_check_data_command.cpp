// `style4d check-data` end to end on tiny synth datasets: a clean one prints its summary and exits 0;
// seeded problems are printed "error|warning: FILE: field: message" with exit 1; a dataset the loader
// refuses exits 2 with its one line; `train` runs the same check first and refuses with the errors.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "cli_run.h"
#include "s4d/data/npy.h"
#include "s4d/io/image_io.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/synth/dataset.h"

namespace fs = std::filesystem;

namespace {

// The exit code of `style4d check-data ARGS` (std::system gives the wait status); -1 when it did not exit.
// A leading dataset folder is passed as --data DIR (the positional DIR, its old spelling, is tested apart).
int run(const std::string& args, const fs::path& log) {
  const bool folder_first = !args.empty() && args[0] != '-';
  const int status = s4d::test::run_style4d("check-data", (folder_first ? "--data " : "") + args, log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
std::string read_text(const fs::path& p) { return s4d::test::read_text(p); }
fs::path fresh_dir(const std::string& name) { return s4d::test::fresh_dir("check_data_" + name); }

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void write_tiny(const fs::path& out, bool dnerf = false) {
  s4d::synth::SynthOptions o;
  o.cams = 4;
  o.frames = 4;
  o.width = 32;
  o.height = 24;
  o.points = 500;
  o.dnerf = dnerf;
  s4d::synth::write_dataset(out, o);
}

s4d::io::ImageF grey(int width, int height) {
  return {width, height, 3, std::vector<float>(static_cast<size_t>(width * height * 3), 0.5f)};
}

}  // namespace

TEST_CASE("check-data on a clean dataset: the summary, no problems, exit 0, --json") {
  const fs::path dir = fresh_dir("clean");
  const fs::path data = dir / "data";
  write_tiny(data);
  REQUIRE(run(data.string() + " --json " + (dir / "report.json").string(), dir / "log.txt") == 0);
  const std::string log = read_text(dir / "log.txt");
  INFO(log);
  CHECK(has(log, "dynerf-frames"));
  CHECK(has(log, "cameras        4, 4 frames per camera"));
  CHECK(has(log, "views          12 train, 4 test"));
  CHECK(has(log, "resolution     32x24 after downscale 1"));
  CHECK(has(log, "time           0 .. 1; 4 train times, 3 train views per time (multi-view)"));
  CHECK(has(log, (data / "points3D.ply").string()));
  CHECK(has(log, "0 errors, 0 warnings"));
  CHECK_FALSE(has(log, "error:"));
  const std::string json = read_text(dir / "report.json");
  CHECK(has(json, "\"errors\": 0"));
  CHECK(has(json, "\"cameras\": 4"));
  CHECK(has(json, "\"problems\": []"));

  REQUIRE(run(data.string() + " --downscale 2", dir / "log.txt") == 0);
  CHECK(has(read_text(dir / "log.txt"), "resolution     16x12 after downscale 2"));
}

TEST_CASE("check-data names each seeded DyNeRF problem by file and field, exit 1; train refuses the dataset") {
  const fs::path dir = fresh_dir("dynerf");
  const fs::path data = dir / "data";
  write_tiny(data);
  s4d::io::write_png(data / "cam02" / "0002.png", grey(40, 30));
  // cam03 turned half round about its down axis (LLFF columns right and back negated).
  s4d::data::NpyArray poses = s4d::data::read_npy(data / "poses_bounds.npy");
  for (size_t r = 0; r < 3; ++r) {
    poses.values[3 * 17 + r * 5 + 1] *= -1;
    poses.values[3 * 17 + r * 5 + 2] *= -1;
  }
  s4d::data::write_npy(data / "poses_bounds.npy", poses);

  REQUIRE(run(data.string() + " --json " + (dir / "report.json").string(), dir / "log.txt") == 1);
  const std::string log = read_text(dir / "log.txt");
  INFO(log);
  CHECK(has(log, "error: " + (data / "cam02" / "0002.png").string() + ": size: is 40x30 but the view's camera"));
  CHECK(has(log, "error: " + (data / "poses_bounds.npy").string() + ": row 3 (cam03): camera faces away from the scene"));
  CHECK(has(log, "2 errors, 0 warnings"));
  const std::string json = read_text(dir / "report.json");
  CHECK(has(json, "\"field\": \"row 3 (cam03)\""));
  CHECK(has(json, "\"severity\": \"error\""));
  CHECK(has(json, "\"errors\": 2"));

  // train runs the same check first: the errors, a non-zero exit, and no run directory.
  const int rc = s4d::test::run_style4d("train", "--data " + data.string() + " --out " + (dir / "run").string() +
                                                     " --preset fast --iters 1", dir / "train.log");
  const std::string train_log = read_text(dir / "train.log");
  INFO(train_log);
  CHECK(rc != 0);
  CHECK(has(train_log, "error: " + (data / "poses_bounds.npy").string() + ": row 3 (cam03): camera faces away"));
  CHECK(has(train_log, "--skip-check"));
  CHECK_FALSE(fs::exists(dir / "run"));
}

TEST_CASE("check-data on a seeded D-NeRF dataset: times out of order (warning), a view facing away, a frame of another size") {
  const fs::path dir = fresh_dir("dnerf");
  const fs::path data = dir / "data";
  write_tiny(data, true);
  const fs::path train_json = data / "transforms_train.json";
  std::vector<s4d::io::CameraView> cams = s4d::io::read_nerf_cameras(train_json, std::pair{32, 24});
  std::swap(cams[1].time, cams[2].time);
  for (size_t i : {0, 2}) {
    for (size_t j = 0; j < 4; ++j) cams[3].world_to_cam[i * 4 + j] *= -1;
  }
  s4d::io::write_nerf_cameras(train_json, cams);
  s4d::io::write_png(data / "test" / "r_002.png", grey(40, 30));

  REQUIRE(run(data.string(), dir / "log.txt") == 1);
  const std::string log = read_text(dir / "log.txt");
  INFO(log);
  CHECK(has(log, "dnerf"));
  CHECK(has(log, "(monocular)"));
  CHECK(has(log, "warning: " + train_json.string() + ": frames[2].time: times out of order"));
  CHECK(has(log, "error: " + train_json.string() + ": frames[3].transform_matrix: camera faces away from the scene"));
  CHECK(has(log, "error: " + (data / "test" / "r_002.png").string() + ": size: is 40x30"));
  CHECK(has(log, "2 errors, 1 warning"));

  // train refuses it; --skip-check trains anyway (a camera facing away does not stop the trainer).
  s4d::io::write_png(data / "test" / "r_002.png", grey(32, 24));
  const std::string train_args = "--data " + data.string() + " --preset fast --iters 2 --fine-iters 2 --out ";
  CHECK(s4d::test::run_style4d("train", train_args + (dir / "refused").string(), dir / "train.log") != 0);
  CHECK(has(read_text(dir / "train.log"), "frames[3].transform_matrix: camera faces away"));
  CHECK_FALSE(fs::exists(dir / "refused"));
  CHECK_MESSAGE(s4d::test::run_style4d("train", train_args + (dir / "run").string() + " --skip-check", dir / "train.log") == 0,
                read_text(dir / "train.log"));
  CHECK(fs::exists(dir / "run" / "train.json"));

  // Only the warning left: exit 0, and the warning still printed.
  for (size_t i : {0, 2}) {
    for (size_t j = 0; j < 4; ++j) cams[3].world_to_cam[i * 4 + j] *= -1;
  }
  s4d::io::write_nerf_cameras(train_json, cams);
  REQUIRE(run(data.string(), dir / "log.txt") == 0);
  CHECK(has(read_text(dir / "log.txt"), "warning: " + train_json.string() + ": frames[2].time: times out of order"));
}

TEST_CASE("check-data exits 2 with the loader's one line when the dataset cannot be loaded") {
  const fs::path dir = fresh_dir("load");
  {
    const fs::path data = dir / "dynerf";
    write_tiny(data);
    fs::remove(data / "cam02" / "0003.png");
    CHECK(run(data.string(), dir / "log.txt") == 2);
    const std::string log = read_text(dir / "log.txt");
    CHECK(has(log, "style4d check-data: error: " + (data / "cam02").string() + ": has 3 frames but cam00 has 4: missing 0003.png (frame 3 of cam00)"));
    CHECK(std::count(log.begin(), log.end(), '\n') == 1);
  }
  {
    const fs::path data = dir / "dnerf";
    write_tiny(data, true);
    const fs::path train_json = data / "transforms_train.json";
    std::vector<s4d::io::CameraView> cams = s4d::io::read_nerf_cameras(train_json, std::pair{32, 24});
    cams[1].time = 1.5;
    s4d::io::write_nerf_cameras(train_json, cams);
    CHECK(run(data.string(), dir / "log.txt") == 2);
    const std::string log = read_text(dir / "log.txt");
    CHECK(has(log, train_json.string() + ": frames[1].time: expected a time in [0, 1], got 1.5"));
    CHECK(std::count(log.begin(), log.end(), '\n') == 1);
  }
  CHECK(run((dir / "nowhere").string(), dir / "log.txt") == 2);
  CHECK(has(read_text(dir / "log.txt"), "not a directory"));
}

TEST_CASE("check-data --help and bad arguments") {
  const fs::path dir = fresh_dir("args");
  REQUIRE(run("--help", dir / "log.txt") == 0);
  const std::string help = read_text(dir / "log.txt");
  CHECK(has(help, "usage: style4d check-data --data DIR"));
  CHECK(has(help, "--downscale"));
  CHECK(has(help, "--json"));
  CHECK(run("", dir / "log.txt") == 2);
  CHECK(has(read_text(dir / "log.txt"), "missing the dataset: --data DIR"));
  CHECK(run((dir).string() + " --downscale 0", dir / "log.txt") == 2);
  CHECK(has(read_text(dir / "log.txt"), "--downscale"));
  REQUIRE(s4d::test::run_style4d("train", "--help", dir / "log.txt") == 0);
  CHECK(has(read_text(dir / "log.txt"), "--skip-check"));
}

TEST_CASE("check-data DIR, the old spelling of --data DIR, still works and says so in one line") {
  const fs::path dir = fresh_dir("positional");
  const fs::path data = dir / "data";
  write_tiny(data);
  REQUIRE(WEXITSTATUS(s4d::test::run_style4d("check-data", data.string(), dir / "log.txt")) == 0);
  const std::string log = read_text(dir / "log.txt");
  CHECK(has(log, "style4d: warning: check-data DIR is an old spelling; use check-data --data DIR"));
  CHECK(log.find("old spelling") == log.rfind("old spelling"));
  CHECK(has(log, "0 errors, 0 warnings"));
}

TEST_CASE("a camera whose frames all decode as one colour is a warning naming the camera and the frames") {
  const fs::path dir = fresh_dir("one_colour");
  const fs::path data = dir / "data";
  write_tiny(data);
  // cam01's frames all black (a video the decoder could not read), cam02's one grey but for one frame.
  const s4d::io::ImageF black{32, 24, 3, std::vector<float>(32 * 24 * 3, 0.0f)};
  const s4d::io::ImageF grey{32, 24, 3, std::vector<float>(32 * 24 * 3, 0.5f)};
  for (int f = 0; f < 4; ++f) {
    s4d::io::write_png(data / "cam01" / ("000" + std::to_string(f) + ".png"), black);
    if (f != 3) s4d::io::write_png(data / "cam02" / ("000" + std::to_string(f) + ".png"), grey);
  }
  REQUIRE(run(data.string(), dir / "log.txt") == 0);  // a warning: the run may still be wanted
  const std::string log = read_text(dir / "log.txt");
  CHECK_MESSAGE(has(log, "warning: " + (data / "cam01").string() + ": frames: camera cam01: every frame sampled "
                         "(cam01/0000, cam01/0001, cam01/0003) decodes as one colour, 0.00,0.00,0.00 (black)"), log);
  CHECK_MESSAGE(!has(log, "camera cam02"), log);  // its last frame has a picture
  CHECK(has(log, "0 errors, 1 warning"));
  // Now cam02 entirely one grey: named with its colour.
  s4d::io::write_png(data / "cam02" / "0003.png", grey);
  REQUIRE(run(data.string(), dir / "log.txt") == 0);
  CHECK_MESSAGE(has(read_text(dir / "log.txt"), "camera cam02: every frame sampled (cam02/0000, cam02/0001, cam02/0003) "
                                                "decodes as one colour, 0.50,0.50,0.50;"), read_text(dir / "log.txt"));
}
