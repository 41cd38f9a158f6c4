// names.h: the strings run files hold for stages, style methods and depth inputs, and their enums.
#include <doctest/doctest.h>

#include <string>

#include "s4d/run/names.h"
#include "s4d/run/train_config.h"

using namespace s4d;

TEST_CASE("run names: each enum value has the string its files hold, and reads back from it") {
  CHECK(std::string(run::stage_name(run::Stage::coarse)) == "static");
  CHECK(std::string(run::stage_name(run::Stage::fine)) == "fine");
  CHECK(std::string(run::geometry_name(run::Stage::coarse)) == "static");
  CHECK(std::string(run::geometry_name(run::Stage::fine)) == "4dgs");
  CHECK(std::string(run::method_name(run::StyleMethod::full)) == "full");
  CHECK(std::string(run::method_name(run::StyleMethod::colors)) == "colors");
  CHECK(std::string(run::method_name(run::StyleMethod::scratch)) == "scratch");
  CHECK(std::string(run::depth_input_name(run::DepthInput::ndc)) == "ndc");
  CHECK(std::string(run::depth_input_name(run::DepthInput::relative)) == "relative");
  for (run::Stage s : {run::Stage::coarse, run::Stage::fine}) {
    CHECK(run::parse_stage(run::stage_name(s)) == s);
    CHECK(run::parse_geometry(run::geometry_name(s)) == s);
  }
  for (run::StyleMethod m : {run::StyleMethod::full, run::StyleMethod::colors, run::StyleMethod::scratch})
    CHECK(run::parse_method(run::method_name(m)) == m);
  for (run::DepthInput d : {run::DepthInput::ndc, run::DepthInput::relative})
    CHECK(run::parse_depth_input(run::depth_input_name(d)) == d);
}

TEST_CASE("run names: the other file's spelling, case changes and unknown names are refused") {
  CHECK_FALSE(run::parse_stage("4dgs"));  // run.json's name is not a checkpoint's
  CHECK_FALSE(run::parse_geometry("fine"));
  CHECK_FALSE(run::parse_stage("Static"));
  CHECK_FALSE(run::parse_method("paint"));
  CHECK_FALSE(run::parse_method(""));
  CHECK_FALSE(run::parse_depth_input("far"));
  CHECK(run::unknown_method("paint") == "method 'paint' is not full, colors or scratch");
}

TEST_CASE("a run's last stage is fine exactly when it has fine iterations") {
  run::TrainConfig c = run::preset_config("fast");
  CHECK(run::last_stage(c) == run::Stage::fine);
  c.fine_iterations = 0;
  CHECK(run::last_stage(c) == run::Stage::coarse);
}
