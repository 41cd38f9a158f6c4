// Interpolation between two styles of one run: the style "(1 - alpha) A + alpha B", itself a style
// file's contents, so it renders through StyledScene like any trained style.
//
// Colours and opacities: their deltas are lerped, so those parts blend exactly. The MLPs: their 52
// weights are lerped. That is valid because every style's MLPs start from the same deterministic
// initialisation (style_trainer.cpp's initial_mlp: the settings' seed and mlp_init, the same defaults
// for every style) and train briefly at a small learning rate, so the hidden layers of two styles stay
// close and the blend's outputs lie close to the lerp of the two styles' outputs (the test measures
// the rendered image against the lerp of the two renders). Styles whose MLPs started from different
// initialisations or read different inputs are refused. An MLP whose last layer is zero adds nothing
// whatever its hidden layers (a "colors" style, which has none, a Gaussian outside a --region, the
// identity initialisation untrained), so its hidden layers are taken from the other style's: the
// blend of such an MLP with a trained one is the trained one with its last layer scaled.
#pragma once
#include <cstdint>

#include "s4d/run/style_file.h"

namespace s4d::scene {

// The blend of `a` and `b` with weight `alpha` in [0, 1] on `b`: alpha 0 gives a's arrays and alpha
// 1 b's, exactly. Method "full" when either has MLPs (depth settings from one that has), else
// "colors". Throws std::invalid_argument for alpha outside [0, 1] (or NaN), a "scratch" style (its own
// geometry), other Gaussian counts or SH layouts, and two MLP styles with other initialisations
// (settings seed, mlp_init) or inputs (depth input, depth scale, input sigmoid).
run::StyleFile blend_styles(const run::StyleFile& a, const run::StyleFile& b, float alpha);

// The original scene as a style: zero changes, no MLPs, for `count` Gaussians with `sh_coeffs` SH
// coefficients per channel; blending a style with it scales the style's changes.
run::StyleFile no_style(uint32_t count, uint32_t sh_coeffs);

}  // namespace s4d::scene
