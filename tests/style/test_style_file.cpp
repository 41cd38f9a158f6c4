// The style file (training/runs/run, s4d/run/style_file.h) and stage 4's settings: round trips, and the clear
// errors for files that are missing, truncated, of the wrong sizes or hold NaN.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "s4d/run/style_file.h"
#include "s4d/style_gaussians/style_config.h"
#include "s4d_style_splat.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

run::StyleFile sample(run::StyleMethod method) {
  run::StyleFile s;
  s.method = method;
  s.settings = {{"note", "test"}};
  s.count = 3, s.sh_coeffs = 4;
  s.sh_delta.assign(3 * 4 * 3, 0.25f);
  s.opacity_delta = {0.1f, -0.2f, 0.3f};
  if (method == run::StyleMethod::full) s.mlp.assign(3 * S4D_STYLE_MLP_STRIDE, -0.5f);
  s.depth_input = run::DepthInput::ndc, s.depth_scale = 2.5f, s.input_sigmoid = true;
  return s;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("s4d_style_file_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string error_of(const fs::path& file) {
  try {
    run::read_style_file(file);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a style file round-trips every array and setting; list_styles finds finished styles only") {
  const fs::path run = scratch("roundtrip");
  for (const run::StyleMethod method : {run::StyleMethod::full, run::StyleMethod::colors, run::StyleMethod::scratch}) {
    const std::string name = run::method_name(method);
    CAPTURE(name);
    run::StyleFile s = method == run::StyleMethod::scratch ? run::StyleFile{} : sample(method);
    s.method = method;
    fs::create_directories(run::style_dir(run, name));
    run::write_style_file(run::style_file_path(run, name), s);
    const run::StyleFile r = run::read_style_file(run::style_file_path(run, name));
    CHECK(r.method == method);
    CHECK(r.count == s.count);
    CHECK(r.sh_delta == s.sh_delta);
    CHECK(r.opacity_delta == s.opacity_delta);
    CHECK(r.mlp == s.mlp);
    CHECK(r.depth_input == s.depth_input);
    CHECK(r.depth_scale == s.depth_scale);
    CHECK(r.input_sigmoid == s.input_sigmoid);
  }
  fs::create_directories(run / "style" / "unfinished");
  CHECK(run::list_styles(run) == std::vector<std::string>{"colors", "full", "scratch"});
  CHECK(run::list_styles(run / "nothing").empty());
}

TEST_CASE("bad style files are refused with the file and the problem named; nothing is written for bad input") {
  const fs::path dir = scratch("errors");
  const fs::path file = dir / "style.s4dstyle";
  CHECK(error_of(file).find("missing") != std::string::npos);

  run::StyleFile wrong = sample(run::StyleMethod::full);
  wrong.mlp.pop_back();
  CHECK_THROWS_AS(run::write_style_file(file, wrong), std::invalid_argument);
  CHECK_FALSE(fs::exists(file));
  run::StyleFile nan = sample(run::StyleMethod::full);
  nan.opacity_delta[1] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(run::write_style_file(file, nan), std::invalid_argument);
  CHECK_FALSE(fs::exists(file));

  run::write_style_file(file, sample(run::StyleMethod::full));
  const auto size = fs::file_size(file);
  fs::resize_file(file, size - 8);
  const std::string truncated = error_of(file);
  CHECK(truncated.find(file.string()) != std::string::npos);
  CHECK(truncated.find("truncated") != std::string::npos);
  std::ofstream(file) << "not a style";
  CHECK(error_of(file).find("not a style4d checkpoint") != std::string::npos);
}

TEST_CASE("stage 4 settings round-trip through JSON and name bad fields") {
  style_gaussians::StyleConfig c;
  c.method = run::StyleMethod::colors, c.iterations = 123, c.mlp_iterations = 50, c.depth_input = run::DepthInput::ndc, c.input_sigmoid = true, c.mlp_init = "identity";
  const style_gaussians::StyleConfig r = style_gaussians::style_config_from_json(style_gaussians::to_json(c));
  CHECK(style_gaussians::to_json(r) == style_gaussians::to_json(c));
  auto message = [](const nlohmann::json& j) {
    try {
      style_gaussians::style_config_from_json(j);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(message({{"methd", "full"}}).find("unknown field 'methd'") != std::string::npos);
  CHECK(message({{"method", "paint"}}).find("method 'paint'") != std::string::npos);
  CHECK(message({{"iterations", "many"}}).find("'iterations' has the wrong type") != std::string::npos);
  CHECK(message({{"depth_input", "far"}}).find("depth_input 'far'") != std::string::npos);
  CHECK(message({{"tv_weight", -1}}).find("tv_weight") != std::string::npos);
}

TEST_CASE("the paper setting trains the MLPs from the start, 1e-4 -> 1e-5, two views a step; tuned is the default") {
  const style_gaussians::StyleConfig tuned = style_gaussians::style_setting("tuned"), paper = style_gaussians::style_setting("paper");
  CHECK(style_gaussians::to_json(tuned) == style_gaussians::to_json(style_gaussians::StyleConfig{}));
  CHECK(tuned.batch == 1);
  CHECK(tuned.mlp_lr_final == 0);
  CHECK(paper.setting == "paper");
  CHECK(paper.mlp_iterations == paper.iterations);
  CHECK(paper.mlp_init == "uniform");
  CHECK(paper.mlp_lr == 1e-4);
  CHECK(paper.mlp_lr_final == 1e-5);
  CHECK(paper.batch == 2);
  CHECK(paper.tv_weight == tuned.tv_weight);
  CHECK_THROWS_WITH_AS(style_gaussians::style_setting("fast"), "style settings: setting 'fast' is not tuned or paper", std::invalid_argument);

  // A shorter stage 4 keeps the paper's MLPs on for all of it, and tuned's for its last steps.
  style_gaussians::StyleConfig p = paper, t = tuned;
  style_gaussians::set_iterations(p, 200);
  style_gaussians::set_iterations(t, 400);
  CHECK(p.mlp_iterations == 200);
  CHECK(t.mlp_iterations == 300);

  // Absent fields take the named setting's defaults; the setting is recorded, so a resumed style
  // with the other one differs.
  const style_gaussians::StyleConfig r = style_gaussians::style_config_from_json({{"setting", "paper"}, {"iterations", 200}});
  CHECK(style_gaussians::to_json(r) == style_gaussians::to_json(p));
  CHECK(style_gaussians::to_json(r) != style_gaussians::to_json(style_gaussians::style_config_from_json({{"iterations", 200}, {"mlp_iterations", 200}})));
  CHECK_THROWS_WITH_AS(style_gaussians::style_config_from_json({{"setting", "paper"}, {"batch", 0}}), "style settings: batch must be positive",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(style_gaussians::style_config_from_json({{"setting", 2}}), "style settings: field 'setting' has the wrong type",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(style_gaussians::style_config_from_json({{"mlp_lr_final", -1e-5}}), "style settings: learning rates must be >= 0",
                       std::invalid_argument);
}
