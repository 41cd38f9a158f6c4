// ssim_vpass: vertical pass of the window over the horizontal statistics, giving mu_x, mu_y and the
// second moments per element; then the SSIM map value S, the three maps of dS that the backward
// filters (scaled by -ssim_weight / n), and per-workgroup partial sums of S and |x - y|.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_loss.h"
#include "flat_group.glsl"
#include "ssim_window.glsl"

layout(local_size_x = S4D_LOSS_WG) in;
layout(push_constant) uniform Push { LossParams p; };
layout(std430, binding = S4D_B_SSIM_V_IMAGE) readonly buffer Image { float image[]; };
layout(std430, binding = S4D_B_SSIM_V_TARGET) readonly buffer Target { float target[]; };
layout(std430, binding = S4D_B_SSIM_V_STATS_H) readonly buffer StatsH { float stats_h[]; };
layout(std430, binding = S4D_B_SSIM_V_DMAPS) writeonly buffer DMaps { float dmaps[]; };
layout(std430, binding = S4D_B_SSIM_V_PARTIALS) writeonly buffer Partials { float partials[]; };

shared float s_sum[2][S4D_LOSS_WG];

void main() {
  uint group = flat_group_id();
  uint lid = gl_LocalInvocationIndex;
  uint e = group * S4D_LOSS_WG + lid;
  float ssim = 0.0, l1 = 0.0;
  if (e < p.n) {
    uvec3 q = loss_coords(e, p.width, p.channels);
    int y0 = int(q.y);
    uint row = p.width * p.channels;
    float s[S4D_SSIM_STATS] = float[](0.0, 0.0, 0.0, 0.0, 0.0);
    for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k) {
      int y = y0 + k;
      if (y < 0 || y >= int(p.height)) continue;
      uint at = e + uint(k * int(row));
      float w = SSIM_TAPS[k + S4D_SSIM_RADIUS];
      for (uint m = 0u; m < S4D_SSIM_STATS; ++m) s[m] += w * stats_h[m * p.n + at];
    }
    float mx = s[0], my = s[1];
    float a1 = 2.0 * mx * my + S4D_SSIM_C1, a2 = 2.0 * (s[4] - mx * my) + S4D_SSIM_C2;
    float b1 = mx * mx + my * my + S4D_SSIM_C1, b2 = (s[2] - mx * mx) + (s[3] - my * my) + S4D_SSIM_C2;
    ssim = a1 * a2 / (b1 * b2);
    // d mean(1 - S) * lambda: the loss decreases as S grows, hence the minus sign.
    float scale = -p.ssim_weight * p.inv_count;
    dmaps[e] = scale * ssim * (2.0 * my / a1 - 2.0 * my / a2 - 2.0 * mx / b1 + 2.0 * mx / b2);  // dS/d mu_x
    dmaps[p.n + e] = scale * ssim * (-1.0 / b2);                                              // dS/d E[x^2]
    dmaps[2u * p.n + e] = scale * ssim * (2.0 / a2);                                          // dS/d E[xy]
    l1 = abs(image[e] - target[e]);
  }
  // Workgroup sums in a fixed tree order, so the loss value is deterministic.
  s_sum[0][lid] = ssim;
  s_sum[1][lid] = l1;
  barrier();
  for (uint stride = S4D_LOSS_WG / 2u; stride > 0u; stride >>= 1) {
    if (lid < stride) {
      s_sum[0][lid] += s_sum[0][lid + stride];
      s_sum[1][lid] += s_sum[1][lid + stride];
    }
    barrier();
  }
  if (lid == 0u) partials[2u * group] = s_sum[0][0], partials[2u * group + 1u] = s_sum[1][0];
}
