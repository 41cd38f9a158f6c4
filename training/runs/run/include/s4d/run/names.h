// What a run's files store as strings (the stage, a style's method and depth input), as enums: the
// one place where they turn into strings and back. Files keep their strings; code compares enums.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace s4d::run {

// The two training stages (ARCHITECTURE.md): coarse = stage 1, static Gaussians; fine = stage 2,
// canonical Gaussians and the 4DGS deformation field.
enum class Stage { coarse, fine };

// As checkpoints, train.json, loss.csv and progress name the stage a run is in: "static", "fine".
const char* stage_name(Stage stage);
std::optional<Stage> parse_stage(std::string_view name);

// As run.json "stage" names what a run's geometry is, by its last stage: "static", "4dgs".
const char* geometry_name(Stage last);
std::optional<Stage> parse_geometry(std::string_view name);

// How a style was trained (stage 4, style_file.h): full = per-Gaussian MLPs with colours and
// opacities (the paper's method), colors = colours and opacities only, scratch = 4DGS retrained on
// the stylized frames (a run of its own).
enum class StyleMethod { full, colors, scratch };

const char* method_name(StyleMethod method);
std::optional<StyleMethod> parse_method(std::string_view name);
// "method 'NAME' is not full, colors or scratch"
std::string unknown_method(std::string_view name);

// How the per-Gaussian MLP reads the ray-hit depth (ALGORITHMS.md 4.3): the GOF/2DGS NDC mapping of
// t*, or the offset t* - z_centre times depth_scale.
enum class DepthInput : uint32_t { ndc = 0, relative = 1 };

const char* depth_input_name(DepthInput input);  // "ndc", "relative"
std::optional<DepthInput> parse_depth_input(std::string_view name);

}  // namespace s4d::run
