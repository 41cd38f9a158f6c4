// loss_grad: vertical pass of the window over the horizontally filtered dS maps, combined into
// dL/dx = (G * dS/dmu_x) + 2x (G * dS/dE[x^2]) + y (G * dS/dE[xy]) + (1 - lambda) sign(x - y) / n.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_loss.h"
#include "flat_group.glsl"
#include "ssim_window.glsl"

layout(local_size_x = S4D_LOSS_WG) in;
layout(push_constant) uniform Push { LossParams p; };
layout(std430, binding = S4D_B_LOSS_GRAD_IMAGE) readonly buffer Image { float image[]; };
layout(std430, binding = S4D_B_LOSS_GRAD_TARGET) readonly buffer Target { float target[]; };
layout(std430, binding = S4D_B_LOSS_GRAD_DMAPS_H) readonly buffer DMapsH { float dmaps_h[]; };
layout(std430, binding = S4D_B_LOSS_GRAD_OUT) writeonly buffer Grad { float grad[]; };

void main() {
  uint e = flat_group_id() * S4D_LOSS_WG + gl_LocalInvocationIndex;
  if (e >= p.n) return;
  uvec3 q = loss_coords(e, p.width, p.channels);
  int y0 = int(q.y);
  uint row = p.width * p.channels;
  float s[S4D_SSIM_DMAPS] = float[](0.0, 0.0, 0.0);
  for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k) {
    int y = y0 + k;
    if (y < 0 || y >= int(p.height)) continue;
    uint at = e + uint(k * int(row));
    float w = SSIM_TAPS[k + S4D_SSIM_RADIUS];
    for (uint m = 0u; m < S4D_SSIM_DMAPS; ++m) s[m] += w * dmaps_h[m * p.n + at];
  }
  float x = image[e], y = target[e];
  float diff = x - y;
  float l1 = diff > 0.0 ? 1.0 : (diff < 0.0 ? -1.0 : 0.0);  // sign, 0 at 0 like torch.abs
  grad[e] = s[0] + 2.0 * x * s[1] + y * s[2] + (1.0 - p.ssim_weight) * p.inv_count * l1;
}
