// style4d train --preset default: 4DGaussians' deformation field (64^3 x 150 planes, 2 levels, C = 16,
// MLP width 128, all five heads) trains on every device, lavapipe included (whose loop limit refused
// it before the per-layer MLP kernels), on a tiny synthetic scene with short stages.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "s4d/train/checkpoint.h"

using namespace s4d;
namespace fs = std::filesystem;

TEST_CASE("train --preset default runs the paper's width-128, five-head field in the 4DGS stage and improves on the static fit") {
  const fs::path dir = test::fresh_dir("train_paper_field");
  REQUIRE(test::run_style4d("synth", "--out " + (dir / "d").string() + " --cams 4 --frames 3 --size 48x36",
                            dir / "synth.log") == 0);
  const fs::path run = dir / "run";
  REQUIRE_MESSAGE(test::run_style4d("train", "--data " + (dir / "d").string() + " --out " + run.string() +
                                                 " --preset default --iters 60 --fine-iters 20 --batch 1",
                                    dir / "train.log") == 0,
                  test::read_text(dir / "train.log"));
  const nlohmann::json j = nlohmann::json::parse(test::read_text(run / "train.json"));
  CHECK(j["stage"] == "fine");
  CHECK(j["settings"]["field_width"] == 128);
  CHECK(j["settings"]["field_heads"] == 31);
  // The field moves the Gaussians: the 4DGS stage beats the static fit it starts from. Measured TODO.
  CHECK(j["test_psnr"].get<double>() > j["static"]["test_psnr"].get<double>() + 0.0);
  const train::Checkpoint cp = train::read_checkpoint(run / "checkpoint" / "state.s4dckpt");
  REQUIRE(cp.extra.size() >= 2);
}
