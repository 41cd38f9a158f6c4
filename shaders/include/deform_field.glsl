// HexPlane lookup for one point (mapping and layout in s4d_deform.h). Needs `p` (DeformParams) and
// the plane buffer `planes[]` before the include.
#ifndef DEFORM_FIELD_GLSL
#define DEFORM_FIELD_GLSL

// One plane's bilinear footprint: texel (x0, y0) and its right / lower neighbours.
struct DeformTap {
  uint base;            // float index of texel (x0, y0), channel 0
  uint step_x, step_y;
  float wx, wy;         // weights of the x0 + 1 and y0 + 1 texels
  float dix, diy;       // d texel coordinate / d grid coordinate; 0 where the border clamps
};

// Grid coordinates: xyz through the (mirrored) AABB; p.time is already the grid's (the host's grid_time).
vec4 deform_coords(vec3 x) { return vec4((x - p.aabb_max.xyz) * p.aabb_scale.xyz - 1.0, p.time); }

// align_corners = True texel coordinate with border clamp; as PyTorch, no gradient on the border.
void texel_coord(float g, uint r, out uint cell, out float w, out float d) {
  float max_index = float(r - 1u);
  precise float t = (g + 1.0) * 0.5 * max_index;
  d = t > 0.0 && t < max_index ? 0.5 * max_index : 0.0;
  float c = clamp(t, 0.0, max_index);
  cell = min(uint(floor(c)), r - 2u);
  w = c - float(cell);
}

// The tap of (level, plane) whose floats start at plane_offset.
DeformTap deform_tap(uint level, uint plane, vec4 g, uint plane_offset) {
  uint au = S4D_DEFORM_PLANE_AXIS_U(plane), av = S4D_DEFORM_PLANE_AXIS_V(plane);
  uint ru = deform_axis_res(p.shape, level, au), rv = deform_axis_res(p.shape, level, av);
  DeformTap t;
  uint x0, y0;
  texel_coord(g[au], ru, x0, t.wx, t.dix);
  texel_coord(g[av], rv, y0, t.wy, t.diy);
  t.step_x = p.shape.channels;
  t.step_y = ru * p.shape.channels;
  t.base = plane_offset + y0 * t.step_y + x0 * t.step_x;
  return t;
}

float tap_value(DeformTap t, uint c) {
  uint i = t.base + c;
  float top = (1.0 - t.wx) * planes[i] + t.wx * planes[i + t.step_x];
  float bottom = (1.0 - t.wx) * planes[i + t.step_y] + t.wx * planes[i + t.step_y + t.step_x];
  return (1.0 - t.wy) * top + t.wy * bottom;
}

// The 6 taps of level l, whose planes start at float `offset` (advanced past them).
void deform_level_taps(uint l, vec4 g, inout uint offset, out DeformTap taps[S4D_DEFORM_PLANES]) {
  for (uint plane = 0u; plane < uint(S4D_DEFORM_PLANES); ++plane) {
    taps[plane] = deform_tap(l, plane, g, offset);
    offset += deform_plane_floats(p.shape, l, plane);
  }
}

#endif  // DEFORM_FIELD_GLSL
