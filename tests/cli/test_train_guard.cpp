// The training guard end to end: a value out of range written into one array of a real run's
// checkpoint (the checksums recomputed, as a bad state that got through would be), then the run
// continued with five more fine steps. Each Gaussian attribute and an Adam moment, in a few
// Gaussians: named in one line, those Gaussians removed, training goes on to the end. Each field
// tensor: named with its part, and training stops at once, since the last good state holds it; the
// checkpoint is left as it was. Stage 4's per-Gaussian style: those Gaussians' style reset.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "s4d/deform/field_config.h"
#include "s4d/model/checkpoint.h"
#include "s4d/run/train_config.h"
#include "s4d_deform.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A finished fast run with its 10 fine steps: 20 static, then 10 fine, checkpoints every 5.
const fs::path& base() {
  static const fs::path run = [] {
    const fs::path dir = test::fresh_dir("train_guard");
    REQUIRE(test::run_style4d("synth", "--out " + (dir / "d").string() + " --cams 4 --frame-count 3 --size 48x36",
                              dir / "synth.log") == 0);
    const int rc = test::run_style4d("train",
                                     "--data " + (dir / "d").string() + " --run " + (dir / "base").string() +
                                         " --preset fast --iters 20 --fine-iters 10 --checkpoint-every 5",
                                     dir / "base.log");
    INFO(test::read_text(dir / "base.log"));
    REQUIRE(rc == 0);
    return dir / "base";
  }();
  return run;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }
void write_json(const fs::path& p, const nlohmann::json& j) { std::ofstream(p) << j.dump(2); }

// A copy of the base run that has five fine steps left, its checkpoint changed by `inject`.
template <class Inject>
fs::path resumable_copy(const std::string& name, Inject inject) {
  const fs::path run = base().parent_path() / name;
  fs::remove_all(run);
  fs::copy(base(), run, fs::copy_options::recursive);
  fs::remove(run / ".lock");
  nlohmann::json train = read_json(run / "train.json"), settings = read_json(run / "run.json");
  train["complete"] = false;
  settings["settings"]["fine_iterations"] = 15;
  write_json(run / "train.json", train), write_json(run / "run.json", settings);
  model::Checkpoint cp = model::read_checkpoint(run / "checkpoint" / "state.s4dckpt");
  inject(cp);
  model::write_checkpoint(run / "checkpoint" / "state.s4dckpt", cp);
  return run;
}

std::vector<float>& extra(model::Checkpoint& cp, const std::string& name) {
  for (auto& [n, v] : cp.extra)
    if (n == name) return v;
  FAIL("no array " << name);
  throw;
}

gpu::DeformShape fast_shape() {
  return deform::deform_shape(run::field_config(run::preset_config("fast"), {-1, -1, -1}, {1, 1, 1}));
}

}  // namespace

TEST_CASE("guard: a few Gaussians out of range in any attribute or moment are named, removed, and training goes on") {
  const uint32_t base_count = read_json(base() / "train.json")["num_gaussians"].get<uint32_t>();
  const double base_psnr = read_json(base() / "train.json")["test_psnr"].get<double>();
  // Attribute, value; the last float of rows 3, 7 and 11 gets it (a log scale of 50: e^50 scene units).
  const std::vector<std::pair<std::string, float>> cases = {
      {"means", 1e30f}, {"log_scales", 50.f}, {"quats", -1e30f}, {"opacity_logits", 1e30f}, {"sh", 1e30f}, {"sh.adam_v", 1e35f}};
  for (const auto& [name, value] : cases) {
    CAPTURE(name);
    const fs::path run = resumable_copy("attr_" + name, [&, value = value, name = name](model::Checkpoint& cp) {
      const size_t dot = name.find('.');
      const std::string attr = name.substr(0, dot);
      for (splat::Attr a : splat::kCloudAttrs) {
        if (attr != splat::attr_name(a)) continue;
        std::vector<float>& v = dot == std::string::npos ? *splat::cloud_arrays(cp.state.cloud)[a] : cp.state.v[a];
        const size_t width = v.size() / cp.state.cloud.size();
        for (size_t g : {3, 7, 11}) v[g * width + width - 1] = value;
      }
    });
    const int rc = test::run_style4d("train", "--run " + run.string(), run.parent_path() / ("l_" + name));
    const std::string log = test::read_text(run.parent_path() / ("l_" + name));
    CHECK_MESSAGE(test::exit_code(rc) == 0, log);
    CHECK_MESSAGE(contains(log, "'" + name + "' of 3 Gaussians ("), log);
    CHECK_MESSAGE(contains(log, "first Gaussian 3)"), log);
    CHECK_MESSAGE(contains(log, "removed those 3 Gaussians and went on"), log);
    const nlohmann::json t = read_json(run / "train.json");
    CHECK(t["complete"] == true);
    CHECK(t["guard_removed"] == 3);
    CHECK(t["num_gaussians"] == base_count - 3);
    // The other Gaussians trained on: five more steps of the same fit.
    CHECK(t["test_psnr"].get<double>() > base_psnr - 1.0);
    const model::Checkpoint end = model::read_checkpoint(run / "checkpoint" / "state.s4dckpt");
    CHECK(end.meta["guard_removed"] == 3);
  }
}

TEST_CASE("guard: a field tensor out of range stops training at once, naming the tensor's part, and changes no checkpoint") {
  const gpu::DeformShape s = fast_shape();
  uint32_t pos_out = 0;  // the pos head's output layer
  for (uint32_t l = 0; l < gpu::deform_layer_count(s); ++l)
    if (gpu::deform_layer_is_head_out(s, l) && gpu::deform_layer_head(s, l) == 0) pos_out = gpu::deform_layer_offset(s, l);
  struct Case {
    std::string array;
    uint32_t at;
    float value;
    std::string part;
  };
  const std::vector<Case> cases = {
      {"field.planes", gpu::deform_plane_offset(s, 0, 2) + 5, 1e30f, "level 0 plane xt"},
      {"field.mlp", pos_out + 1, 1e30f, "head pos output weight"},
      {"field.planes.adam_m", gpu::deform_plane_offset(s, 1, 0), 1e20f, "level 1 plane xy"},
      {"field.mlp.adam_v", 0, 1e35f, "trunk layer 0 weight"}};
  for (const Case& c : cases) {
    CAPTURE(c.array);
    const fs::path run = resumable_copy("tensor_" + c.array, [&](model::Checkpoint& cp) { extra(cp, c.array).at(c.at) = c.value; });
    const std::string before = test::read_text(run / "checkpoint" / "state.s4dckpt");
    const int rc = test::run_style4d("train", "--run " + run.string(), run.parent_path() / ("l_" + c.array));
    const std::string log = test::read_text(run.parent_path() / ("l_" + c.array));
    CHECK_MESSAGE(test::exit_code(rc) != 0, log);
    CHECK_MESSAGE(contains(log, "'" + c.array + "' at 1 entry ("), log);
    CHECK_MESSAGE(contains(log, "in " + c.part + ")"), log);
    CHECK_MESSAGE(contains(log, "holds the cause too"), log);
    CHECK_MESSAGE(contains(log, "training stopped"), log);
    CHECK(test::read_text(run / "checkpoint" / "state.s4dckpt") == before);
  }
}

TEST_CASE("guard: stage 4's style out of range in a few Gaussians is named, reset, and the style is written") {
  const fs::path dir = base().parent_path();
  const fs::path run = dir / "styled";
  fs::remove_all(run);
  fs::copy(base(), run, fs::copy_options::recursive);
  fs::remove(run / ".lock");
  REQUIRE(test::run_style4d("make-style", "--out " + (dir / "style.png").string() + " --size 64", dir / "make_style.log") == 0);
  const std::string stylize = "--run " + run.string() + " --style-image " + (dir / "style.png").string() +
                              " --style s --iters 20 --mlp-iters 10 --checkpoint-every 10 --spiral-frames 2";
  REQUIRE_MESSAGE(test::run_style4d("stylize", stylize, dir / "stylize.log") == 0, test::read_text(dir / "stylize.log"));
  // The finished stage's checkpoint with three Gaussians' SH deltas and one's MLP out of range; the
  // same command again continues from it.
  const fs::path checkpoint = run / "style" / "s" / "checkpoint.s4dckpt";
  model::Checkpoint cp = model::read_checkpoint(checkpoint);
  std::vector<float>& sh = extra(cp, "sh_delta");
  const size_t width = sh.size() / cp.meta["count"].get<size_t>();
  for (size_t g : {3, 7}) sh[g * width] = 1e30f;
  std::vector<float>& mlp = extra(cp, "mlp");
  mlp[11 * (mlp.size() / cp.meta["count"].get<size_t>()) + 2] = -1e20f;
  model::write_checkpoint(checkpoint, cp);
  fs::remove(run / "style" / "s" / "style.s4dstyle");
  const int rc = test::run_style4d("stylize", stylize, dir / "stylize_again.log");
  const std::string log = test::read_text(dir / "stylize_again.log");
  REQUIRE_MESSAGE(test::exit_code(rc) == 0, log);
  CHECK_MESSAGE(contains(log, "'sh_delta' of 2 Gaussians (up to 1e+30; first Gaussian 3)"), log);
  CHECK_MESSAGE(contains(log, "'mlp' of 1 Gaussian (up to 1e+20; first Gaussian 11)"), log);
  CHECK_MESSAGE(contains(log, "reset the style of those 3 Gaussians and went on"), log);
  CHECK(fs::exists(run / "style" / "s" / "style.s4dstyle"));
  const model::Checkpoint after = model::read_checkpoint(checkpoint);
  CHECK(after.meta["guard_reset"] == 3);
  CHECK(extra(const_cast<model::Checkpoint&>(after), "sh_delta")[3 * width] == 0.0f);
}
