// The block of a layer set that a workgroup of deform_fwd or deform_bwd computes (sets, blocks and
// the scratch row layout in s4d_deform.h). Needs `p` (DeformParams) and flat_group.glsl first.
#ifndef DEFORM_MLP_GLSL
#define DEFORM_MLP_GLSL

#if S4D_DEFORM_ROWS != 4 || S4D_DEFORM_BLOCK != 4
#error "deform_fwd and deform_bwd hold a block's rows and outputs (inputs) in uvec4 / mat4"
#endif

// Workgroups are tiles of S4D_DEFORM_TILE Gaussians x the set's blocks, tile-major, so consecutive
// workgroups reuse a tile's scratch rows. Sets `rows` (this invocation's S4D_DEFORM_ROWS scratch
// rows, S4D_DEFORM_WG apart, clamped to the pass: a row past it computes the last row's values and
// writes nothing, so loops stay uniform), `live` (which rows are in the pass), the block's layer
// and its block within that layer. False for workgroups past the tiles x blocks (a split dispatch
// rounds up); the whole workgroup returns.
bool deform_block(bool backward, bool shared_input, out uvec4 rows, out bvec4 live, out uint layer, out uint block) {
  uint count = p.n - p.first, tiles = (count + uint(S4D_DEFORM_TILE) - 1u) / uint(S4D_DEFORM_TILE);
  uint blocks = deform_set_blocks(p.shape, p.layer, p.layers, backward, shared_input), g = flat_group_id();
  if (g >= tiles * blocks) return false;
  uvec4 r = g / blocks * uint(S4D_DEFORM_TILE) + gl_LocalInvocationIndex + uvec4(0u, 1u, 2u, 3u) * uint(S4D_DEFORM_WG);
  live = lessThan(r, uvec4(count));
  rows = min(r, uvec4(count - 1u));
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
