// --style NAME [--mix NAME2 --alpha A]: which style `render --run` and `view` show, or the blend of two
// (training/runs/scene/style_blend.h), parsed the same way for both; and --half, how `render`,
// `bench --run` and `view` hold the trained model on the device.
#pragma once
#include "args.h"
#include "s4d/scene/trained_run.h"

namespace s4d::cli {

// The option specs of --mix and --alpha (--style's own help differs between the commands).
OptionSpec mix_spec();
OptionSpec alpha_spec();
OptionSpec half_spec();

// --half: SH and style MLP weights as packed halves (splat::Storage::f16), else floats.
splat::Storage parse_storage(const Args& args);

// Throws std::invalid_argument for --mix without --alpha, --alpha without --mix, and an --alpha that
// is not a number in [0, 1].
scene::StyleChoice parse_style_choice(const Args& args);

}  // namespace s4d::cli
