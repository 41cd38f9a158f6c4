#include "s4d/run/style_file.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "s4d/run/checkpoint.h"
#include "s4d/run/run_dir.h"
#include "s4d_style_splat.h"

namespace s4d::run {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFileName = "style.s4dstyle";

[[noreturn]] void fail(const fs::path& path, const std::string& what) { throw std::runtime_error(path.string() + ": " + what); }

void check_sizes(const StyleFile& s, const std::string& where, bool reading) {
  auto bad = [&](const std::string& what) {
    if (reading) throw std::runtime_error(where + ": " + what);
    throw std::invalid_argument(where + ": " + what);
  };
  if (s.method == StyleMethod::scratch) {
    if (!s.sh_delta.empty() || !s.opacity_delta.empty() || !s.mlp.empty()) bad("a scratch style holds no arrays");
    return;
  }
  auto expect = [&](const char* name, size_t got, size_t want) {
    if (got != want)
      bad(std::string("array '") + name + "' holds " + std::to_string(got) + " floats, expected " + std::to_string(want) +
          " for " + std::to_string(s.count) + " Gaussians");
  };
  expect("style.sh_delta", s.sh_delta.size(), size_t{s.count} * s.sh_coeffs * 3);
  expect("style.opacity_delta", s.opacity_delta.size(), s.count);
  expect("style.mlp", s.mlp.size(), s.method == StyleMethod::full ? size_t{s.count} * S4D_STYLE_MLP_STRIDE : 0);
  if (!(s.depth_scale > 0.0f)) bad("depth_scale must be positive");
}

}  // namespace

fs::path style_dir(const fs::path& run_root, const std::string& name) { return RunDir{run_root}.style_dir() / name; }
fs::path style_file_path(const fs::path& run_root, const std::string& name) { return style_dir(run_root, name) / kFileName; }
fs::path style_image_path(const fs::path& run_root, const std::string& name) { return style_dir(run_root, name) / "style_image.png"; }

void write_style_file(const fs::path& path, const StyleFile& s) {
  check_sizes(s, path.string(), false);
  const nlohmann::json meta = {{"format", "style4d style"},
                               {"method", method_name(s.method)},
                               {"settings", s.settings},
                               {"count", s.count},
                               {"sh_coeffs", s.sh_coeffs},
                               {"depth_input", depth_input_name(s.depth_input)},
                               {"depth_scale", s.depth_scale},
                               {"input_sigmoid", s.input_sigmoid}};
  std::vector<NamedArray> arrays;
  if (s.method != StyleMethod::scratch) arrays = {{"style.sh_delta", s.sh_delta}, {"style.opacity_delta", s.opacity_delta}};
  if (s.method == StyleMethod::full) arrays.emplace_back("style.mlp", s.mlp);
  const io::GaussianCloud none;  // a style holds no Gaussians: the trainer's arrays are listed empty
  write_checkpoint(path, {meta, none, {}, arrays});
}

StyleFile read_style_file(const fs::path& path) {
  if (!fs::exists(path)) fail(path, "missing (train the style with style4d stylize)");
  const Checkpoint cp = read_checkpoint(path);
  StyleFile s;
  try {
    if (cp.meta.value("format", "") != "style4d style") fail(path, "not a style file (a training checkpoint?)");
    const std::string method = cp.meta.at("method").get<std::string>();
    const std::optional<StyleMethod> known = parse_method(method);
    if (!known) fail(path, unknown_method(method));
    s.method = *known;
    s.settings = cp.meta.at("settings");
    s.count = cp.meta.at("count").get<uint32_t>();
    s.sh_coeffs = cp.meta.at("sh_coeffs").get<uint32_t>();
    const std::string depth = cp.meta.at("depth_input").get<std::string>();
    const std::optional<DepthInput> input = parse_depth_input(depth);
    if (!input) fail(path, "depth_input '" + depth + "' is not ndc or relative");
    s.depth_input = *input;
    s.depth_scale = cp.meta.at("depth_scale").get<float>();
    s.input_sigmoid = cp.meta.at("input_sigmoid").get<bool>();
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("malformed settings: ") + e.what());
  }
  for (const auto& [name, values] : cp.extra) {
    if (name == "style.sh_delta") s.sh_delta = values;
    else if (name == "style.opacity_delta") s.opacity_delta = values;
    else if (name == "style.mlp") s.mlp = values;
    else fail(path, "unexpected array '" + name + "'");
  }
  check_sizes(s, path.string(), true);
  return s;
}

std::vector<std::string> list_styles(const fs::path& run_root) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(RunDir{run_root}.style_dir(), ec))
    if (e.is_directory() && fs::exists(e.path() / kFileName)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace s4d::run
