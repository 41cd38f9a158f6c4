// densify_gather: dst[j*w + k] = src[source(j)*w + k] for every output slot j and word k < w, bit for
// bit (any 32-bit per-Gaussian array). With zero_new, copies and split children get 0 instead (the
// Adam moments of new entries, graphdeco semantics). One thread per output word.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_densify.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DENSIFY_WG) in;
layout(push_constant) uniform Push { SlotParams p; };  // n = output slots
layout(std430, binding = S4D_B_GATHER_SLOTS) readonly buffer Slots { uint slots[]; };  // [M]
layout(std430, binding = S4D_B_GATHER_SRC) readonly buffer Src { uint src[]; };        // [N*w]
layout(std430, binding = S4D_B_GATHER_DST) writeonly buffer Dst { uint dst[]; };       // [M*w]

void main() {
  uint e = flat_group_id() * S4D_DENSIFY_WG + gl_LocalInvocationIndex;
  if (e >= p.n * p.width) return;
  uint j = e / p.width, k = e - j * p.width;
  uint slot = slots[j];
  bool fresh = (slot >> S4D_DENSIFY_SLOT_SHIFT) != S4D_DENSIFY_SLOT_ORIGINAL;
  dst[e] = (p.zero_new != 0u && fresh) ? 0u : src[(slot & S4D_DENSIFY_SLOT_INDEX_MASK) * p.width + k];
}
