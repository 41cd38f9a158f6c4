#include "s4d/scene/style_blend.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d_style_splat.h"

namespace s4d::scene {

namespace {

[[noreturn]] void refuse(const std::string& why) { throw std::invalid_argument("cannot blend these styles: " + why); }

// The settings that fix an MLP's initial weights (style_config.h); null where a file does not say.
nlohmann::json init_setting(const run::StyleFile& s, const char* key) {
  return s.settings.is_object() && s.settings.contains(key) ? s.settings.at(key) : nlohmann::json();
}

void check_mlps_match(const run::StyleFile& a, const run::StyleFile& b) {
  for (const char* key : {"seed", "mlp_init"})
    if (init_setting(a, key) != init_setting(b, key))
      refuse(std::string("their MLPs started from other initialisations (") + key + " " + init_setting(a, key).dump() +
             " and " + init_setting(b, key).dump() + "), so their weights do not correspond");
  if (a.depth_input != b.depth_input || a.depth_scale != b.depth_scale || a.input_sigmoid != b.input_sigmoid)
    refuse("their MLPs read other inputs (depth input, depth scale or input sigmoid differ)");
}

std::vector<float> lerp_all(const std::vector<float>& a, const std::vector<float>& b, float alpha) {
  std::vector<float> out(a.size());
  for (size_t k = 0; k < a.size(); ++k) out[k] = std::lerp(a[k], b[k], alpha);
  return out;
}

// True when the MLP at `w` adds nothing: its last layer (W3, b3) is zero, so its output pre-activations
// are 0 whatever the hidden layers give.
bool adds_nothing(const float* w) {
  return std::all_of(w + S4D_STYLE_MLP_W3, w + S4D_STYLE_MLP_STRIDE, [](float x) { return x == 0.0f; });
}

// The per-Gaussian MLP blend (style_blend.h): hidden layers of an MLP that adds nothing come from the
// other style; a style without MLPs stands for zero last layers.
std::vector<float> blend_mlps(const run::StyleFile& a, const run::StyleFile& b, float alpha) {
  const uint32_t n = S4D_STYLE_MLP_STRIDE;
  std::vector<float> out(size_t{a.count} * n);
  for (size_t i = 0; i < a.count; ++i) {
    const float* pa = a.mlp.empty() ? nullptr : &a.mlp[i * n];
    const float* pb = b.mlp.empty() ? nullptr : &b.mlp[i * n];
    const float* hidden_a = pb == nullptr || (pa != nullptr && !adds_nothing(pa)) ? pa : pb;
    const float* hidden_b = pa == nullptr || (pb != nullptr && !adds_nothing(pb)) ? pb : pa;
    float* o = &out[i * n];
    for (uint32_t k = 0; k < S4D_STYLE_MLP_W3; ++k) o[k] = std::lerp(hidden_a[k], hidden_b[k], alpha);
    for (uint32_t k = S4D_STYLE_MLP_W3; k < n; ++k)
      o[k] = std::lerp(pa != nullptr ? pa[k] : 0.0f, pb != nullptr ? pb[k] : 0.0f, alpha);
  }
  return out;
}

}  // namespace

run::StyleFile blend_styles(const run::StyleFile& a, const run::StyleFile& b, float alpha) {
  if (!(alpha >= 0.0f && alpha <= 1.0f)) refuse("the blend factor " + std::to_string(alpha) + " is not in [0, 1]");
  if (a.method == run::StyleMethod::scratch || b.method == run::StyleMethod::scratch)
    refuse("a style trained with --method scratch is a run of its own (RUN/style/NAME/run), not changes to this "
           "run's Gaussians");
  if (a.count != b.count)
    refuse("they were trained for " + std::to_string(a.count) + " and " + std::to_string(b.count) + " Gaussians");
  if (a.sh_coeffs != b.sh_coeffs)
    refuse("they store " + std::to_string(a.sh_coeffs) + " and " + std::to_string(b.sh_coeffs) +
           " SH coefficients per channel");
  const bool mlp_a = !a.mlp.empty(), mlp_b = !b.mlp.empty();
  if (mlp_a && mlp_b) check_mlps_match(a, b);
  const run::StyleFile& inputs = mlp_a || !mlp_b ? a : b;  // where the MLP's depth settings come from
  run::StyleFile out;
  out.method = mlp_a || mlp_b ? run::StyleMethod::full : run::StyleMethod::colors;
  out.settings = {{"blend", {{"alpha", alpha}, {"a", a.settings}, {"b", b.settings}}}};
  out.count = a.count;
  out.sh_coeffs = a.sh_coeffs;
  out.sh_delta = lerp_all(a.sh_delta, b.sh_delta, alpha);
  out.opacity_delta = lerp_all(a.opacity_delta, b.opacity_delta, alpha);
  if (out.method == run::StyleMethod::full) out.mlp = blend_mlps(a, b, alpha);
  out.depth_input = inputs.depth_input;
  out.depth_scale = inputs.depth_scale;
  out.input_sigmoid = inputs.input_sigmoid;
  return out;
}

run::StyleFile no_style(uint32_t count, uint32_t sh_coeffs) {
  run::StyleFile s;
  s.method = run::StyleMethod::colors;
  s.settings = {{"original", true}};
  s.count = count;
  s.sh_coeffs = sh_coeffs;
  s.sh_delta.assign(size_t{count} * sh_coeffs * 3, 0.0f);
  s.opacity_delta.assign(count, 0.0f);
  return s;
}

}  // namespace s4d::scene
