// project_fwd: per Gaussian, activations, EWA projection, conic, 3-sigma radius, tile rectangle,
// colour (SH or the colour buffer) and the depth sort key (ALGORITHMS.md 1.3). Culled Gaussians get
// zero outputs, tiles_touched 0 and the culled depth key. S4D_SH_HALF=1 (project_fwd_half) reads the
// SH as packed halves (half_storage.glsl), the render side's half storage; the colour buffer stays
// float.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "flat_group.glsl"
#include "splat_project.glsl"
#include "splat_sh.glsl"
#include "half_storage.glsl"
#ifndef S4D_SH_HALF
#define S4D_SH_HALF 0
#endif

layout(local_size_x = S4D_SPLAT_WG) in;
layout(push_constant) uniform Push { ProjectParams p; };
layout(std430, binding = S4D_B_PROJ_MEANS) readonly buffer Means { float means[]; };
layout(std430, binding = S4D_B_PROJ_LOG_SCALES) readonly buffer LogScales { float log_scales[]; };
layout(std430, binding = S4D_B_PROJ_QUATS) readonly buffer Quats { float quats[]; };
layout(std430, binding = S4D_B_PROJ_OPACITY_LOGITS) readonly buffer OpacityLogits { float opacity_logits[]; };
#if S4D_SH_HALF
layout(std430, binding = S4D_B_PROJ_SH) readonly buffer Sh { uint sh_words[]; };  // [ceil(N*K*3 / 2)] f16 pairs
float sh_at(uint j) { return half_element(sh_words[j >> 1], j); }
#else
layout(std430, binding = S4D_B_PROJ_SH) readonly buffer Sh { float sh[]; };  // [N, K, 3]
float sh_at(uint j) { return sh[j]; }
#endif
layout(std430, binding = S4D_B_PROJ_COLORS) readonly buffer Colors { float colors[]; };
layout(std430, binding = S4D_B_PROJ_XY) writeonly buffer Xy { vec2 xy[]; };
layout(std430, binding = S4D_B_PROJ_CONIC_OPACITY) writeonly buffer ConicOpacity { vec4 conic_opacity[]; };
layout(std430, binding = S4D_B_PROJ_COLOR_DEPTH) writeonly buffer ColorDepth { vec4 color_depth[]; };
layout(std430, binding = S4D_B_PROJ_INFO) writeonly buffer Info { uvec4 info[]; };
layout(std430, binding = S4D_B_PROJ_DEPTH_KEYS) writeonly buffer DepthKeys { uint depth_keys[]; };
layout(std430, binding = S4D_B_PROJ_TILES_TOUCHED) writeonly buffer TilesTouched { uint tiles_touched[]; };

// Tile index of a pixel coordinate, clamped to [0, hi] in float first so huge or negative
// coordinates never reach an out-of-range float-to-int conversion.
uint tile_of(float x, uint hi) { return uint(clamp(x / float(S4D_TILE_SIZE), 0.0, float(hi))); }

void main() {
  uint i = flat_group_id() * S4D_SPLAT_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  xy[i] = vec2(0.0);
  conic_opacity[i] = vec4(0.0);
  color_depth[i] = vec4(0.0);
  info[i] = uvec4(0u);
  depth_keys[i] = S4D_CULLED_DEPTH_KEY;
  tiles_touched[i] = 0u;

  vec3 mu = vec3(means[3 * i], means[3 * i + 1], means[3 * i + 2]);
  vec3 ls = vec3(log_scales[3 * i], log_scales[3 * i + 1], log_scales[3 * i + 2]);
  vec4 rq = vec4(quats[4 * i], quats[4 * i + 1], quats[4 * i + 2], quats[4 * i + 3]);
  SplatProjection pr = splat_project_one(p.cam, mu, ls, rq);
  float logit = opacity_logits[i];
  if (!pr.visible || isnan(logit)) return;

  float u = p.cam.intrinsics.x * pr.t.x / pr.t.z + p.cam.intrinsics.z;
  float v = p.cam.intrinsics.y * pr.t.y / pr.t.z + p.cam.intrinsics.w;
  float mid = 0.5 * (pr.a + pr.c);
  float root = sqrt(max(S4D_MIN_EIGEN_GAP, mid * mid - pr.det));
  float r = ceil(S4D_SIGMA_EXTENT * sqrt(mid + root));
  vec3 conic = vec3(pr.c, -pr.b, pr.a) / pr.det;
  // Overflowing inputs (for example a scale of 1e30) cull instead of poisoning the tile lists.
  if (any(isinf(vec4(u, v, r, conic.x))) || any(isnan(vec4(u, v, r, conic.x))) || any(isinf(conic.yz)) ||
      any(isnan(conic.yz)))
    return;
  uint tx = p.cam.size.z, ty = p.cam.size.w;
  uvec4 rect = uvec4(tile_of(u - r, tx), tile_of(v - r, ty), tile_of(u + r + float(S4D_TILE_SIZE - 1), tx),
                     tile_of(v + r + float(S4D_TILE_SIZE - 1), ty));
  uint area = (rect.z - rect.x) * (rect.w - rect.y);
  if (area == 0u) return;

  float opacity = 1.0 / (1.0 + exp(-logit));
  vec3 rgb;
  uint clamped = 0u;
  if ((p.flags & S4D_SPLAT_USE_COLORS) != 0u) {
    rgb = vec3(colors[3 * i], colors[3 * i + 1], colors[3 * i + 2]);
  } else {
    float Y[S4D_MAX_SH_COEFFS];
    sh_basis(p.sh_degree, pr.dir, Y);
    uint num_active = (p.sh_degree + 1u) * (p.sh_degree + 1u);
    for (uint ch = 0u; ch < 3u; ++ch) {
      float acc = 0.5;
      for (uint k = 0u; k < num_active; ++k) acc += Y[k] * sh_at((i * p.sh_coeffs + k) * 3u + ch);
      if (acc < 0.0) clamped |= 1u << ch;
      rgb[ch] = max(acc, 0.0);
    }
  }

  xy[i] = vec2(u, v);
  conic_opacity[i] = vec4(conic, opacity);
  color_depth[i] = vec4(rgb, pr.t.z);
  info[i] = uvec4(rect.x | (rect.y << 16), rect.z | (rect.w << 16), uint(min(r, 1e9)), clamped);
  depth_keys[i] = floatBitsToUint(pr.t.z);  // z > S4D_NEAR_Z > 0: the IEEE bits sort like the values
  tiles_touched[i] = area;
}
