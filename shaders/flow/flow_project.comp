// flow_project: one thread per Gaussian. Reads its world mean (means [N*3]), transforms it by the
// camera's world_to_cam and writes the pinhole projection u = fx x/z + cx, v = fy y/z + cy and a
// validity flag (z > S4D_NEAR_Z and finite) into screen [N*3]. Same arithmetic as project_fwd's mean,
// so a Gaussian lands where the rasterizer draws it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_flow.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_FLOW_WG) in;
layout(push_constant) uniform Push { FlowProjectParams p; };
layout(std430, binding = S4D_B_FLOWP_MEANS) readonly buffer Means { float means[]; };     // [N, 3]
layout(std430, binding = S4D_B_FLOWP_SCREEN) writeonly buffer Screen { float screen[]; };  // [N, 3]

void main() {
  uint i = flat_group_id() * S4D_FLOW_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  vec3 mu = vec3(means[3 * i], means[3 * i + 1], means[3 * i + 2]);
  vec4 V[3] = vec4[3](p.cam.view_row0, p.cam.view_row1, p.cam.view_row2);
  vec3 t;
  for (int r = 0; r < 3; ++r) t[r] = V[r].x * mu.x + V[r].y * mu.y + V[r].z * mu.z + V[r].w;  // as splat_project_one
  float u = p.cam.intrinsics.x * t.x / t.z + p.cam.intrinsics.z;
  float v = p.cam.intrinsics.y * t.y / t.z + p.cam.intrinsics.w;
  // "Not > near" also rejects NaN; an infinite mean gives a non-finite u or v.
  bool valid = t.z > S4D_NEAR_Z && !isinf(u) && !isnan(u) && !isinf(v) && !isnan(v);
  uint o = S4D_FLOW_SCREEN_STRIDE * i;
  screen[o + S4D_FLOW_SCREEN_U] = valid ? u : 0.0;
  screen[o + S4D_FLOW_SCREEN_V] = valid ? v : 0.0;
  screen[o + S4D_FLOW_SCREEN_VALID] = valid ? 1.0 : 0.0;
}
