// tv_grad: squared total variation of an image, the stage-4 smoothness term on the rendered frame.
// Each invocation owns one element: it adds that element's TV gradient to grad (no races) and
// contributes its right and down differences to its workgroup's partial sum of the value.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_loss.h"
#include "flat_group.glsl"
#include "ssim_window.glsl"

layout(local_size_x = S4D_LOSS_WG) in;
layout(push_constant) uniform Push { TvParams p; };
layout(std430, binding = S4D_B_TV_IMAGE) readonly buffer Image { float image[]; };
layout(std430, binding = S4D_B_TV_GRAD) buffer Grad { float grad[]; };
layout(std430, binding = S4D_B_TV_PARTIALS) writeonly buffer Partials { float partials[]; };

shared float s_sum[S4D_LOSS_WG];

void main() {
  uint group = flat_group_id();
  uint lid = gl_LocalInvocationIndex;
  uint e = group * S4D_LOSS_WG + lid;
  float value = 0.0;
  if (e < p.n) {
    uvec3 q = loss_coords(e, p.width, p.channels);
    uint row = p.width * p.channels;
    float x = image[e], g = 0.0;
    if (q.x > 0u) g += x - image[e - p.channels];
    if (q.y > 0u) g += x - image[e - row];
    if (q.x + 1u < p.width) {
      float d = image[e + p.channels] - x;
      g -= d, value += d * d;
    }
    if (q.y + 1u < p.height) {
      float d = image[e + row] - x;
      g -= d, value += d * d;
    }
    grad[e] += 2.0 * p.weight * p.inv_pairs * g;
  }
  // Workgroup sum in a fixed tree order, so the value is deterministic.
  s_sum[lid] = value;
  barrier();
  for (uint stride = S4D_LOSS_WG / 2u; stride > 0u; stride >>= 1) {
    if (lid < stride) s_sum[lid] += s_sum[lid + stride];
    barrier();
  }
  if (lid == 0u) partials[group] = s_sum[0];
}
