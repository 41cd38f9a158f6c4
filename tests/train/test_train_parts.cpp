// The training stage's host-side parts: initial cloud, checkpoints, settings, view order.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include <nlohmann/json.hpp>

#include "host_state_fixture.h"
#include "s4d/deform/motion_split.h"
#include "s4d/model/checkpoint.h"
#include "s4d/run/train_config.h"
#include "s4d/train/evaluate.h"
#include "s4d/train/init_cloud.h"
#include "s4d/train/split_state.h"
#include "s4d/train/view_sampler.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}


}  // namespace

TEST_CASE("mean_sq_dist_3nn matches brute force on a surface-like cloud and an isolated cluster") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<float> p;
  for (int i = 0; i < 1500; ++i) p.insert(p.end(), {u(rng) * 4, u(rng) * 2, 0.01f * u(rng)});  // a thin slab
  for (int i = 0; i < 5; ++i) p.insert(p.end(), {40 + u(rng), 40, 40});                        // far away, sparse
  const std::vector<float> fast = train::mean_sq_dist_3nn(p);
  const size_t n = p.size() / 3;
  for (size_t i = 0; i < n; ++i) {
    std::vector<float> d;
    for (size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      float s = 0;
      for (int a = 0; a < 3; ++a) s += (p[j * 3 + a] - p[i * 3 + a]) * (p[j * 3 + a] - p[i * 3 + a]);
      d.push_back(s);
    }
    std::partial_sort(d.begin(), d.begin() + 3, d.end());
    CHECK(fast[i] == (d[0] + d[1] + d[2]) / 3);  // the same float operations in the same order: exact
  }
}

TEST_CASE("cloud_from_points follows graphdeco's initialisation") {
  const std::vector<float> pts = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::vector<float> cols = {0.5f, 0.5f, 0.5f, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const io::GaussianCloud c = train::cloud_from_points(pts, cols, 2);
  REQUIRE(c.size() == 4);
  CHECK(c.sh.size() == 4 * 9 * 3);
  // Point 0's 3 neighbours are all at distance 1: scale 1, log 0.
  CHECK(c.log_scales[0] == doctest::Approx(0.0).epsilon(1e-6));
  CHECK(c.quats[0] == 1.0f);
  CHECK(1 / (1 + std::exp(-c.opacity_logits[0])) == doctest::Approx(0.1));
  CHECK(0.5f + 0.28209479f * c.sh[9 * 3] == doctest::Approx(1.0));  // point 1 is red: DC reproduces it
  CHECK(c.sh[9 * 3 + 3] == 0.0f);                                    // higher coefficients start at zero
  CHECK_THROWS_AS(train::cloud_from_points({0, 0}, {0, 0}, 0), std::invalid_argument);
  CHECK_THROWS_AS(train::cloud_from_points({0, 0, NAN}, {0, 0, 0}, 0), std::invalid_argument);
}

TEST_CASE("a checkpoint round-trips exactly and refuses non-finite values, truncation and other files") {
  const fs::path dir = fresh_dir("s4d_checkpoint_test");
  model::Checkpoint cp{{{"iteration", 42}, {"sampler", "x"}}, test::small_state(50, 1, 3), {{"field.planes", {1, 2, 3}}, {"field.mlp", {}}}};
  write_checkpoint(dir / "a.s4dckpt", cp);
  const model::Checkpoint back = model::read_checkpoint(dir / "a.s4dckpt");
  CHECK(back.meta == cp.meta);
  CHECK(back.state.cloud.means == cp.state.cloud.means);
  CHECK(back.state.cloud.sh == cp.state.cloud.sh);
  CHECK(back.state.m[splat::Attr::sh] == cp.state.m[splat::Attr::sh]);
  CHECK(back.state.v[splat::Attr::quats] == cp.state.v[splat::Attr::quats]);
  CHECK(back.state.stats[model::kMaxRadius] == cp.state.stats[model::kMaxRadius]);
  CHECK(back.extra == cp.extra);

  model::Checkpoint bad = cp;
  bad.state.m[splat::Attr::opacity_logits][7] = NAN;
  CHECK_THROWS_WITH_AS(write_checkpoint(dir / "a.s4dckpt", bad), doctest::Contains("opacity_logits.adam_m"),
                       std::invalid_argument);
  CHECK(model::read_checkpoint(dir / "a.s4dckpt").state.cloud.means == cp.state.cloud.means);  // old file intact

  model::Checkpoint bad_extra = cp;
  bad_extra.extra[0].second[1] = INFINITY;
  CHECK_THROWS_WITH_AS(write_checkpoint(dir / "b.s4dckpt", bad_extra), doctest::Contains("field.planes"), std::invalid_argument);

  const auto size = fs::file_size(dir / "a.s4dckpt");
  fs::copy_file(dir / "a.s4dckpt", dir / "cut.s4dckpt");
  fs::resize_file(dir / "cut.s4dckpt", size - 10);
  CHECK_THROWS_WITH_AS(model::read_checkpoint(dir / "cut.s4dckpt"), doctest::Contains("truncated"), std::runtime_error);
  std::ofstream(dir / "text.s4dckpt") << "hello";
  CHECK_THROWS_WITH_AS(model::read_checkpoint(dir / "text.s4dckpt"), doctest::Contains("not a style4d checkpoint"),
                       std::runtime_error);
  CHECK_THROWS_WITH_AS(model::read_checkpoint(dir / "missing.s4dckpt"), doctest::Contains("missing.s4dckpt"),
                       std::runtime_error);
}

TEST_CASE("what renders reads a trainer's checkpoint file through s4d_run: the Gaussians and the field, the trainer's arrays apart") {
  const fs::path dir = fresh_dir("s4d_checkpoint_file_test");
  const model::Checkpoint cp{{{"iteration", 7}}, test::small_state(20, 1, 5), {{"field.planes", {4, 5}}}};
  model::write_checkpoint(dir / "a.s4dckpt", cp);
  const run::Checkpoint file = run::read_checkpoint(dir / "a.s4dckpt");
  CHECK(file.meta == cp.meta);
  CHECK(file.cloud.means == cp.state.cloud.means);
  CHECK(file.cloud.sh == cp.state.cloud.sh);
  CHECK(file.extra == cp.extra);  // the field's arrays only: the trainer's come before them
  const std::vector<std::string>& names = run::trainer_array_names();
  REQUIRE(names.size() == 2 * splat::kCloudAttrCount + model::kStatCount);
  REQUIRE(file.trainer.size() == names.size());
  CHECK(names[2] == "log_scales.adam_m");
  CHECK(file.trainer[2] == cp.state.m[splat::Attr::log_scales]);
  CHECK(names[3] == "log_scales.adam_v");
  CHECK(file.trainer[3] == cp.state.v[splat::Attr::log_scales]);
  CHECK(names.back() == "max_radius");
  CHECK(file.trainer.back() == cp.state.stats[model::kMaxRadius]);

  // A file of no Gaussians (a style file) lists the trainer's arrays empty; a file of Gaussians needs all of them.
  const io::GaussianCloud none;
  const std::vector<run::NamedArray> arrays = {{"style.x", {1, 2}}};
  run::write_checkpoint(dir / "b.s4dckpt", {nlohmann::json::object(), none, {}, arrays});
  const run::Checkpoint b = run::read_checkpoint(dir / "b.s4dckpt");
  CHECK(b.trainer == std::vector<std::vector<float>>(names.size()));
  CHECK(b.extra == arrays);
  CHECK_THROWS_WITH_AS(run::write_checkpoint(dir / "c.s4dckpt", {cp.meta, cp.state.cloud, {}, cp.extra}),
                       doctest::Contains("0 trainer arrays for 20 Gaussians, expected 13"), std::invalid_argument);
  CHECK(!fs::exists(dir / "c.s4dckpt"));
}

TEST_CASE("settings round-trip through JSON and --iters rescales the schedules") {
  run::TrainConfig c = run::preset_config("fast");
  c.background = {1, 0.5f, 0};
  CHECK(run::to_json(run::config_from_json(run::to_json(c))) == run::to_json(c));
  run::TrainConfig d = run::preset_config("default");
  CHECK(d.iterations == 3000);  // 4DGaussians' coarse stage, then its DyNeRF fine steps
  CHECK(d.fine_iterations == 14000);
  run::set_iterations(d, 300);
  CHECK(d.iterations == 300);
  CHECK(d.densify_until == 1500);
  CHECK(d.densify_from == 50);
  CHECK(d.densify_every == 100);  // the interval is a rate, kept
  CHECK_THROWS_AS(run::preset_config("turbo"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(run::config_from_json(nlohmann::json{{"iterations", "many"}}), doctest::Contains("iterations"),
                       std::runtime_error);
}

TEST_CASE("the view sampler visits every view once per epoch and resumes identically") {
  train::ViewSampler s(7, 11);
  std::set<uint32_t> epoch;
  for (int i = 0; i < 7; ++i) epoch.insert(s.next());
  CHECK(epoch.size() == 7);
  s.next();
  s.next();
  const std::string saved = s.save();
  std::vector<uint32_t> a, b;
  for (int i = 0; i < 20; ++i) a.push_back(s.next());
  train::ViewSampler t(7, 999);
  t.load(saved);
  for (int i = 0; i < 20; ++i) b.push_back(t.next());
  CHECK(a == b);
  train::ViewSampler other(8, 0);
  CHECK_THROWS_AS(other.load(saved), std::runtime_error);
}

TEST_CASE("the motion split puts still Gaussians last, stably, and moves every per-Gaussian array with them") {
  const std::vector<uint32_t> mask = {1, 0, 0, 1, 0, 1, 0};
  const deform::MotionSplit split = deform::split_by_motion(mask);
  CHECK(split.order == std::vector<uint32_t>{1, 2, 4, 6, 0, 3, 5});
  CHECK(split.still_count == 3);
  CHECK_FALSE(split.identity());
  CHECK(deform::split_by_motion(deform::tail_mask(7, 3)).identity());  // what checkpoints hold: already in order
  CHECK(deform::tail_mask(4, 1) == std::vector<uint32_t>{0, 0, 0, 1});
  const model::HostState s = test::small_state(mask.size(), 1, 3);
  const model::HostState g = train::gather_state(s, split.order);
  auto row = [](const std::vector<float>& v, size_t width, size_t i) {
    return std::vector<float>(v.begin() + i * width, v.begin() + (i + 1) * width);
  };
  for (size_t j = 0; j < mask.size(); ++j) {
    const size_t i = split.order[j];
    CHECK(row(g.cloud.means, 3, j) == row(s.cloud.means, 3, i));
    CHECK(row(g.cloud.log_scales, 3, j) == row(s.cloud.log_scales, 3, i));
    CHECK(row(g.cloud.quats, 4, j) == row(s.cloud.quats, 4, i));
    CHECK(row(g.cloud.opacity_logits, 1, j) == row(s.cloud.opacity_logits, 1, i));
    CHECK(row(g.cloud.sh, 12, j) == row(s.cloud.sh, 12, i));
    for (splat::Attr a : splat::kCloudAttrs) {
      CHECK(row(g.m[a], splat::attr_floats(a, 4), j) == row(s.m[a], splat::attr_floats(a, 4), i));
      CHECK(row(g.v[a], splat::attr_floats(a, 4), j) == row(s.v[a], splat::attr_floats(a, 4), i));
    }
    for (uint32_t k = 0; k < model::kStatCount; ++k) CHECK(g.stats[k][j] == s.stats[k][i]);
  }
  CHECK(g.cloud.sh_degree == 1);
  CHECK_THROWS_AS(train::gather_state(s, std::vector<uint32_t>{0, 1}), std::invalid_argument);
}
