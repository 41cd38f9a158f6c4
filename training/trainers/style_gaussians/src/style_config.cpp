#include "s4d/style_gaussians/style_config.h"

#include <optional>
#include <stdexcept>

namespace s4d::style_gaussians {

StyleConfig style_setting(const std::string& name) {
  StyleConfig c;
  if (name == "tuned") return c;
  if (name != "paper") throw std::invalid_argument("style settings: setting '" + name + "' is not tuned or paper");
  c.setting = name;
  c.mlp_iterations = c.iterations;
  c.mlp_init = "uniform";
  c.mlp_lr = 1e-4, c.mlp_lr_final = 1e-5;
  c.batch = 2;
  return c;
}

void set_iterations(StyleConfig& c, uint32_t iterations) {
  if (c.mlp_iterations == c.iterations) c.mlp_iterations = iterations;
  c.iterations = iterations;
}

nlohmann::json to_json(const StyleConfig& c) {
  return {{"setting", c.setting},
          {"method", run::method_name(c.method)},
          {"stylizer", c.stylizer},
          {"strength", c.strength},
          {"iterations", c.iterations},
          {"mlp_iterations", c.mlp_iterations},
          {"batch", c.batch},
          {"seed", c.seed},
          {"train_colors", c.train_colors},
          {"sh_dc_lr", c.sh_dc_lr},
          {"sh_rest_lr", c.sh_rest_lr},
          {"opacity_lr", c.opacity_lr},
          {"mlp_lr", c.mlp_lr},
          {"mlp_lr_final", c.mlp_lr_final},
          {"ssim_weight", c.ssim_weight},
          {"tv_weight", c.tv_weight},
          {"depth_input", run::depth_input_name(c.depth_input)},
          {"depth_scale", c.depth_scale},
          {"input_sigmoid", c.input_sigmoid},
          {"mlp_init", c.mlp_init},
          {"region", c.region},
          {"test_every", c.test_every},
          {"checkpoint_every", c.checkpoint_every}};
}

StyleConfig style_config_from_json(const nlohmann::json& j) {
  const nlohmann::json known = to_json(StyleConfig{});
  for (const auto& [key, value] : j.items())
    if (!known.contains(key)) throw std::invalid_argument("style settings: unknown field '" + key + "'");
  auto get = [&](const char* key, auto& field) {
    if (!j.contains(key)) return;
    try {
      j.at(key).get_to(field);
    } catch (const nlohmann::json::exception&) {
      throw std::invalid_argument(std::string("style settings: field '") + key + "' has the wrong type");
    }
  };
  std::string setting = "tuned";
  get("setting", setting);
  StyleConfig c = style_setting(setting);
  std::string method = run::method_name(c.method);
  get("method", method);
  c.method = method_setting(method);
  get("stylizer", c.stylizer), get("strength", c.strength);
  uint32_t iterations = c.iterations;
  get("iterations", iterations);
  set_iterations(c, iterations);
  get("mlp_iterations", c.mlp_iterations), get("batch", c.batch), get("mlp_lr_final", c.mlp_lr_final);
  get("seed", c.seed), get("train_colors", c.train_colors), get("sh_dc_lr", c.sh_dc_lr), get("sh_rest_lr", c.sh_rest_lr);
  get("opacity_lr", c.opacity_lr), get("mlp_lr", c.mlp_lr), get("ssim_weight", c.ssim_weight), get("tv_weight", c.tv_weight);
  std::string depth = run::depth_input_name(c.depth_input);
  get("depth_input", depth);
  const std::optional<run::DepthInput> input = run::parse_depth_input(depth);
  if (!input) throw std::invalid_argument("style settings: depth_input '" + depth + "' is not ndc or relative");
  c.depth_input = *input;
  get("depth_scale", c.depth_scale), get("input_sigmoid", c.input_sigmoid), get("mlp_init", c.mlp_init);
  get("region", c.region);
  get("test_every", c.test_every), get("checkpoint_every", c.checkpoint_every);
  validate(c);
  return c;
}

void validate(const StyleConfig& c) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("style settings: " + what); };
  if (c.setting != "tuned" && c.setting != "paper") bad("setting '" + c.setting + "' is not tuned or paper");
  if (c.mlp_init != "uniform" && c.mlp_init != "identity") bad("mlp_init '" + c.mlp_init + "' is not uniform or identity");
  if (!(c.strength >= 0 && c.strength <= 1)) bad("strength must be in [0, 1]");
  if (c.iterations == 0) bad("iterations must be positive");
  if (c.mlp_iterations > c.iterations) bad("mlp_iterations must be at most iterations");
  if (c.batch == 0) bad("batch must be positive");
  if (!(c.ssim_weight >= 0 && c.ssim_weight <= 1)) bad("ssim_weight must be in [0, 1]");
  if (!(c.tv_weight >= 0)) bad("tv_weight must be >= 0");
  if (!(c.depth_scale >= 0)) bad("depth_scale must be >= 0 (0: automatic)");
  for (double lr : {c.sh_dc_lr, c.sh_rest_lr, c.opacity_lr, c.mlp_lr, c.mlp_lr_final})
    if (!(lr >= 0)) bad("learning rates must be >= 0");
  if (!c.region.empty() && (c.region.size() != 6 || !(c.region[0] < c.region[3] && c.region[1] < c.region[4] && c.region[2] < c.region[5])))
    bad("region must be empty or 6 numbers min x, y, z, max x, y, z with min < max");
  if (c.test_every == 0 || c.checkpoint_every == 0) bad("test_every and checkpoint_every must be positive");
}

run::StyleMethod method_setting(const std::string& name) {
  const std::optional<run::StyleMethod> method = run::parse_method(name);
  if (!method) throw std::invalid_argument("style settings: " + run::unknown_method(name));
  return *method;
}

}  // namespace s4d::style_gaussians
