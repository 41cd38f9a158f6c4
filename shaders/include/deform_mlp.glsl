// The block of a layer set that a workgroup of deform_fwd or deform_bwd computes (sets, blocks and
// the scratch row layout in s4d_deform.h). Needs `p` (DeformParams) and flat_group.glsl first.
#ifndef DEFORM_MLP_GLSL
#define DEFORM_MLP_GLSL

// Workgroups are Gaussian tiles x the set's blocks, tile-major, so consecutive workgroups reuse a
// tile's scratch rows. Sets `row` (this invocation's scratch row, clamped to the pass: a row past
// it computes the last row's values and writes nothing, so loops stay uniform), `live` (the row is
// in the pass), the block's layer and its block within that layer. False for workgroups past the
// tiles x blocks (a split dispatch rounds up); the whole workgroup returns.
bool deform_block(bool backward, bool shared_input, out uint row, out bool live, out uint layer, out uint block) {
  uint rows = p.n - p.first, tiles = (rows + uint(S4D_DEFORM_WG) - 1u) / uint(S4D_DEFORM_WG);
  uint blocks = deform_set_blocks(p.shape, p.layer, p.layers, backward, shared_input), g = flat_group_id();
  if (g >= tiles * blocks) return false;
  uint r = g / blocks * uint(S4D_DEFORM_WG) + gl_LocalInvocationIndex;
  live = r < rows;
  row = min(r, rows - 1u);
  layer = p.layer;
  block = g % blocks;
  for (uint k = 1u; k < (shared_input ? 1u : p.layers); ++k) {  // the set's layer holding the block
    uint n = deform_set_blocks(p.shape, layer, 1u, backward, false);
    if (block < n) break;
    block -= n;
    layer += 2u;
  }
  return true;
}

// Four indices from `first`, clamped to `count` (a partial block repeats the last one).
uvec4 deform_quad(uint first, uint count) { return min(uvec4(first) + uvec4(0u, 1u, 2u, 3u), uvec4(count - 1u)); }

#endif  // DEFORM_MLP_GLSL
