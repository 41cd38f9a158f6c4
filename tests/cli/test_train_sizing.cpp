// A model sized to the scene: a new run whose frames show no motion skips the deformation field
// (train/scene_motion.h), says so in one line and in train.json's recipe; --fine-iters still trains
// one; a scene that moves keeps it. On `synth --still` (every frame the built-in scene at t = 0)
// and the built-in scene itself.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }

}  // namespace

TEST_CASE("a capture that does not move gets no deformation field unless --fine-iters asks; one that moves keeps it") {
  const fs::path dir = test::fresh_dir("train_sizing");
  for (const char* name : {"still", "moving"}) {
    const std::string still = std::string(name) == "still" ? " --still" : "";
    REQUIRE(test::run_style4d("synth", "--out " + (dir / name).string() + " --cams 4 --frame-count 3 --size 48x36" + still,
                              dir / (std::string(name) + "_synth.log")) == 0);
  }
  // The still capture: the 4DGS stage is skipped.
  REQUIRE(test::run_style4d("train", "--data " + (dir / "still").string() + " --run " + (dir / "r_still").string() +
                                         " --preset fast --iters 30",
                            dir / "still.log") == 0);
  const std::string log = test::read_text(dir / "still.log");
  CHECK_MESSAGE(contains(log, "no deformation field: the frames show no motion: up to 0 % of a camera's pixels change "
                              "(over 4 cameras, 12 frame pairs"), log);
  const nlohmann::json t = read_json(dir / "r_still" / "train.json");
  CHECK(t["stage"] == "static");
  CHECK(t["settings"]["fine_iterations"] == 0);
  CHECK(read_json(dir / "r_still" / "run.json")["settings"]["fine_iterations"] == 0);
  const nlohmann::json& field = t["dataset"]["recipe"]["deformation_field"];
  CHECK(field["motion"] == "still");
  CHECK(field["changed_share"] == 0.0);
  CHECK(field["trained"].get<std::string>().starts_with("no:"));

  // Asked for, the field is trained on the same capture.
  REQUIRE(test::run_style4d("train", "--data " + (dir / "still").string() + " --run " + (dir / "r_asked").string() +
                                         " --preset fast --iters 30 --fine-iters 3",
                            dir / "asked.log") == 0);
  const nlohmann::json asked = read_json(dir / "r_asked" / "train.json");
  CHECK(asked["stage"] == "fine");
  CHECK(asked["dataset"]["recipe"]["deformation_field"]["trained"] == "yes: --fine-iters asked for it");

  // The built-in scene moves: its sliding box alone changes a tenth of a camera's pixels.
  REQUIRE(test::run_style4d("train", "--data " + (dir / "moving").string() + " --run " + (dir / "r_moving").string() +
                                         " --preset fast --iters 30 --set fine_iterations=3",
                            dir / "moving.log") == 0);
  const nlohmann::json moving = read_json(dir / "r_moving" / "train.json");
  CHECK(moving["stage"] == "fine");
  const nlohmann::json& m = moving["dataset"]["recipe"]["deformation_field"];
  CHECK(m["motion"] == "moving");
  CHECK(m["changed_share"].get<double>() > 0.1);
}
