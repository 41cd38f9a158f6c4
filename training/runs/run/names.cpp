#include "s4d/run/names.h"

namespace s4d::run {

const char* stage_name(Stage stage) { return stage == Stage::fine ? "fine" : "static"; }

std::optional<Stage> parse_stage(std::string_view name) {
  if (name == "static") return Stage::coarse;
  if (name == "fine") return Stage::fine;
  return std::nullopt;
}

const char* geometry_name(Stage last) { return last == Stage::fine ? "4dgs" : "static"; }

std::optional<Stage> parse_geometry(std::string_view name) {
  if (name == "static") return Stage::coarse;
  if (name == "4dgs") return Stage::fine;
  return std::nullopt;
}

const char* method_name(StyleMethod method) {
  static constexpr const char* kNames[] = {"full", "colors", "scratch"};  // in enum order
  return kNames[static_cast<int>(method)];
}

std::optional<StyleMethod> parse_method(std::string_view name) {
  for (StyleMethod m : {StyleMethod::full, StyleMethod::colors, StyleMethod::scratch})
    if (name == method_name(m)) return m;
  return std::nullopt;
}

std::string unknown_method(std::string_view name) {
  return "method '" + std::string(name) + "' is not full, colors or scratch";
}

const char* depth_input_name(DepthInput input) { return input == DepthInput::ndc ? "ndc" : "relative"; }

std::optional<DepthInput> parse_depth_input(std::string_view name) {
  if (name == "ndc") return DepthInput::ndc;
  if (name == "relative") return DepthInput::relative;
  return std::nullopt;
}

}  // namespace s4d::run
