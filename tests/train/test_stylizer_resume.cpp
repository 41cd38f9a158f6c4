// train-stylizer's --losses sets (which of HGST's terms and levels train) and its checkpoint: a run
// interrupted by --steps and continued gives the losses and weights of an uninterrupted one, bit for
// bit, and a folder that cannot be continued is refused by name. Tiny random encoder widths and
// procedural images keep it to a few seconds on lavapipe.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "nn_fixture.h"
#include "s4d/io/image_io.h"
#include "s4d/frame_stylizers/builtin_style.h"
#include "s4d/stylizer_train/loss_sets.h"
#include "s4d/stylizer_train/stylizer_trainer.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

// A scratch folder with a tiny vgg_normalised, one content and one style image, and settings for
// short runs on them.
struct Fixture {
  test::ScratchDir dir{"stylizer_resume"};
  stylizer_train::StylizerTrainSettings s;
  Fixture() {
    std::mt19937 rng(37);
    test::write_params(dir / "vgg.safetensors", test::random_vgg(nn::VggWidths{{4, 6, 8, 12, 10}}, 5, rng));
    fs::create_directories(dir / "content");
    fs::create_directories(dir / "styles");
    io::write_png(dir / "content" / "a.png", frame_stylizers::builtin_style(64, 1));
    io::write_png(dir / "styles" / "b.png", frame_stylizers::builtin_style(64, 2));
    s.content_dir = dir / "content";
    s.styles_dir = dir / "styles";
    s.vgg = dir / "vgg.safetensors";
    s.batch = 2;
    s.resize = 56;
    s.crop = 40;
    s.lr = 1e-3;
    s.seed = 5;  // at these widths seed 9's random decoder has every ReLU of a layer dead: a constant image
  }
  std::vector<nn::MccLossValues> train() { return stylizer_train::train_stylizer(test::context(), s); }
};

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

// The message of the std::exception train() throws; empty when it does not throw.
std::string refusal(Fixture& f) {
  try {
    f.train();
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST_CASE("the --losses sets switch HGST's terms and levels, and the loss follows them") {
  using stylizer_train::loss_set;
  const nn::MccLossWeights hgst;
  for (const char* name : {"mccnet", "content"}) {
    const auto set = loss_set(name);
    CHECK(set.levels.style == std::vector<int>{1, 2, 3, 4, 5});
    CHECK(set.weights.tv == 0.0f);
    CHECK(set.weights.selfsim == 0.0f);
    CHECK(set.weights.ccpl == 0.0f);
    CHECK(set.weights.content == hgst.content);
    CHECK(set.weights.noise == hgst.noise);
  }
  // ccpl: MCCNet's + CCPL's own (relu2_1..relu4_1, 8 anchors, no jitter, heads trained, weight 5);
  // lcl: content + HGST's (relu3_1, relu4_1, 16 anchors, jitter, heads fixed, weight 4).
  const auto ccpl = loss_set("ccpl"), lcl = loss_set("lcl"), full = loss_set("full");
  CHECK(ccpl.levels.content == std::vector<int>{4, 5});
  CHECK(ccpl.weights.ccpl == 5.0f);
  CHECK(ccpl.ccpl.levels == std::vector<int>{2, 3, 4});
  CHECK(ccpl.ccpl.anchors == 8);
  CHECK(!ccpl.ccpl.jitter);
  CHECK(ccpl.ccpl.train_heads);
  CHECK(lcl.levels.content == std::vector<int>{3, 4, 5});
  CHECK(lcl.weights.tv == 0.0f);
  for (const auto* set : {&lcl, &full}) {
    CHECK(set->weights.ccpl == 4.0f);
    CHECK(set->ccpl.levels == std::vector<int>{3, 4});
    CHECK(set->ccpl.anchors == 16);
    CHECK(set->ccpl.jitter);
    CHECK(!set->ccpl.train_heads);
  }
  CHECK(loss_set("mccnet").levels.content == std::vector<int>{4, 5});
  CHECK(loss_set("content").levels.content == std::vector<int>{3, 4, 5});
  CHECK(loss_set("full").levels.content == std::vector<int>{3, 4, 5});
  CHECK(loss_set("full").levels.style == std::vector<int>{5, 2, 3, 4, 5});
  CHECK(loss_set("full").weights.tv == hgst.tv);
  CHECK(loss_set("full").weights.selfsim == hgst.selfsim);
  CHECK_THROWS_WITH(loss_set("cbam"), "--losses: expected one of mccnet, ccpl, content, lcl, full, got 'cbam'");

  // One step of each: the off terms are still measured but left out of the total.
  Fixture f;
  f.s.steps = 1;
  for (const std::string name : {"mccnet", "ccpl", "lcl", "full"}) {
    f.s.losses = name;
    f.s.out = f.dir / name;
    const nn::MccLossValues v = f.train().at(0);
    CHECK(v.tv > 0);
    CHECK(v.selfsim > 0);
    CHECK(v.ccpl > 0);
    const nn::MccLossWeights w = loss_set(name).weights;
    const double on = w.content * v.content + w.style * v.style + w.identity1 * v.identity1 + w.identity2 * v.identity2 +
                      w.noise * v.noise + w.ccpl * v.ccpl;
    // v.tv is the pairs' mean, the total has HGST's sum over the batch.
    const double off = double(hgst.tv) * f.s.batch * v.tv + hgst.selfsim * v.selfsim;
    // The total sums the two pairs' totals, the terms are their means: equal up to rounding.
    CHECK(v.total == doctest::Approx(name == "full" ? on + off : on).epsilon(1e-9));
  }
}

TEST_CASE("a ccpl run, whose heads Adam trains, continues its checkpoint step for step") {
  Fixture f;
  f.s.losses = "ccpl";
  f.s.batch = 1;
  f.s.steps = 4;
  f.s.out = f.dir / "whole";
  const auto whole = f.train();
  f.s.out = f.dir / "parts";
  f.s.steps = 2;
  f.train();
  f.s.steps = 4;
  const auto second = f.train();
  REQUIRE(second.size() == 2);
  for (size_t i = 0; i < 2; ++i) {
    CHECK(second[i].ccpl == whole[i + 2].ccpl);
    CHECK(second[i].total == whole[i + 2].total);
  }
  // The checkpoint holds the heads and their moments, so it is byte-identical too.
  for (const char* file : {"decoder.safetensors", "mcc_module.safetensors", "checkpoint.safetensors"})
    CHECK_MESSAGE(read_bytes(f.dir / "whole" / file) == read_bytes(f.dir / "parts" / file), file);
}

TEST_CASE("train-stylizer continues its checkpoint step for step and never starts over silently") {
  Fixture f;
  f.s.save_every = 2;
  f.s.steps = 6;
  f.s.out = f.dir / "whole";
  const auto whole = f.train();
  f.s.out = f.dir / "parts";
  f.s.steps = 3;
  const auto first = f.train();
  CHECK(fs::exists(f.s.out / "checkpoint.safetensors"));
  f.s.steps = 6;
  const auto second = f.train();
  REQUIRE(whole.size() == 6);
  REQUIRE(first.size() == 3);
  REQUIRE(second.size() == 3);
  for (size_t i = 0; i < 3; ++i) {
    CHECK(first[i].total == whole[i].total);
    CHECK(second[i].total == whole[i + 3].total);
  }
  for (const char* file : {"decoder.safetensors", "mcc_module.safetensors", "checkpoint.safetensors"})
    CHECK_MESSAGE(read_bytes(f.dir / "whole" / file) == read_bytes(f.dir / "parts" / file), file);

  const std::string checkpoint = (f.dir / "parts" / "checkpoint.safetensors").string();
  CHECK(refusal(f) == "--steps 6: " + checkpoint + " is already at step 6");
  f.s.steps = 8;
  f.s.losses = "mccnet";
  CHECK(refusal(f) == "--losses mccnet: " + checkpoint + " was trained with --losses full; pass --restart to start over");
  f.s.losses = "full";
  f.s.batch = 3;  // every setting a continued run must repeat is refused by name; one stands for them
  CHECK(refusal(f) == "--batch 3: " + checkpoint + " was trained with --batch 2; pass --restart to start over");
  f.s.batch = 2;
  f.s.lr = 1.5e-3;
  CHECK(refusal(f) == "--lr 0.0015: " + checkpoint + " was trained with --lr 0.001; pass --restart to start over");
  f.s.lr = 1e-3;
  f.s.init = f.dir / "whole";
  CHECK(refusal(f).find("--init: --out " + f.s.out.string() + " continues from its checkpoint") == 0);
  f.s.init.clear();
  std::mt19937 rng(38);
  test::write_params(f.dir / "vgg2.safetensors", test::random_vgg(nn::VggWidths{{4, 6, 8, 12, 10}}, 5, rng));
  f.s.vgg = f.dir / "vgg2.safetensors";
  CHECK(refusal(f) == "--vgg " + f.s.vgg.string() + " is not the encoder " + (f.s.out / "vgg_normalised.safetensors").string() +
                          " was trained with; pass --restart to start over");
  f.s.vgg = f.dir / "vgg.safetensors";

  // --restart trains the folder again from the start: the uninterrupted run's first steps.
  f.s.restart = true;
  f.s.steps = 2;
  const auto again = f.train();
  REQUIRE(again.size() == 2);
  CHECK(again[1].total == whole[1].total);
  f.s.restart = false;
  // Weights of another step than the checkpoint's are refused, not mixed.
  fs::copy_file(f.dir / "whole" / "decoder.safetensors", f.s.out / "decoder.safetensors", fs::copy_options::overwrite_existing);
  f.s.steps = 4;
  CHECK(refusal(f) == (f.s.out / "decoder.safetensors").string() + " is at step 6, " + checkpoint +
                          " at step 2; pass --restart to start over");
  // A folder with other files and no checkpoint.
  f.s.out = f.dir / "content";
  CHECK(refusal(f) == "--out " + f.s.out.string() +
                          " holds files but no checkpoint.safetensors to continue; pass --restart to train it from the start");
}
