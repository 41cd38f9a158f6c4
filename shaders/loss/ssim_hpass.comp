// ssim_hpass: horizontal pass of the separable SSIM window with zero padding. Forward (mode 0):
// the five statistics x, y, x^2, y^2, xy. Backward (mode 1): the three dS maps, because the window
// is symmetric and the zero-padded convolution's adjoint is the same filter.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_loss.h"
#include "flat_group.glsl"
#include "ssim_window.glsl"

layout(local_size_x = S4D_LOSS_WG) in;
layout(push_constant) uniform Push { LossParams p; };
layout(std430, binding = S4D_B_SSIM_H_IN_A) readonly buffer InA { float in_a[]; };
layout(std430, binding = S4D_B_SSIM_H_IN_B) readonly buffer InB { float in_b[]; };
layout(std430, binding = S4D_B_SSIM_H_OUT) writeonly buffer Out { float out_h[]; };

void main() {
  uint e = flat_group_id() * S4D_LOSS_WG + gl_LocalInvocationIndex;
  if (e >= p.n) return;
  uvec3 q = loss_coords(e, p.width, p.channels);
  int x0 = int(q.x);
  if (p.mode == 0u) {
    float s[S4D_SSIM_STATS] = float[](0.0, 0.0, 0.0, 0.0, 0.0);
    for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k) {
      int x = x0 + k;
      if (x < 0 || x >= int(p.width)) continue;
      uint at = e + uint(k * int(p.channels));
      float w = SSIM_TAPS[k + S4D_SSIM_RADIUS], a = in_a[at], b = in_b[at];
      s[0] += w * a, s[1] += w * b, s[2] += w * a * a, s[3] += w * b * b, s[4] += w * a * b;
    }
    for (uint k = 0u; k < S4D_SSIM_STATS; ++k) out_h[k * p.n + e] = s[k];
  } else {
    float s[S4D_SSIM_DMAPS] = float[](0.0, 0.0, 0.0);
    for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k) {
      int x = x0 + k;
      if (x < 0 || x >= int(p.width)) continue;
      uint at = e + uint(k * int(p.channels));
      float w = SSIM_TAPS[k + S4D_SSIM_RADIUS];
      for (uint m = 0u; m < S4D_SSIM_DMAPS; ++m) s[m] += w * in_a[m * p.n + at];
    }
    for (uint m = 0u; m < S4D_SSIM_DMAPS; ++m) out_h[m * p.n + e] = s[m];
  }
}
