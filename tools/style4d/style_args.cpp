#include "style_args.h"

#include <cstdlib>
#include <stdexcept>

namespace s4d::cli {

OptionSpec mix_spec() {
  return {"mix", "blend --style (default original) with this style of the run; needs --alpha", true, "NAME"};
}

OptionSpec alpha_spec() {
  return {"alpha", "with --mix: the weight of the --mix style, in [0, 1] (0: --style alone, 1: --mix alone)", true, "A"};
}

OptionSpec half_spec() {
  return {"half", "hold SH and style MLP weights on the device as half-precision floats (half their memory;\n"
                  "                        docs/rasterizer.md has the accuracy cost)", false, ""};
}

splat::Storage parse_storage(const Args& args) { return args.flag("half") ? splat::Storage::f16 : splat::Storage::f32; }

scene::StyleChoice parse_style_choice(const Args& args) {
  scene::StyleChoice choice{.style = args.get_or("style", "original"), .mix = args.get_or("mix", "")};
  if (args.get("mix") && choice.mix.empty()) throw UsageError("--mix: expected a style name");
  if (args.get("mix") && !args.get("alpha"))
    throw UsageError("--mix " + choice.mix + " needs --alpha A, the weight of " + choice.mix + " in [0, 1]");
  if (!args.get("alpha")) return choice;
  if (!args.get("mix")) throw UsageError("--alpha needs --mix NAME, the style to blend --style with");
  const std::string text = *args.get("alpha");
  char* end = nullptr;
  choice.alpha = std::strtof(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(choice.alpha >= 0.0f && choice.alpha <= 1.0f))
    throw UsageError("--alpha: expected a number in [0, 1], got '" + text + "'");
  return choice;
}

}  // namespace s4d::cli
