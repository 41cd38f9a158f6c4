// The pixels and output channels of a convolution invocation, and the store of its accumulators.
// Each invocation computes a strip of S4D_NN_CONV_PIX pixels along x for a block of
// S4D_NN_CONV_COUT output channels (s4d_nn.h), so every value it loads feeds several accumulators:
// on llvmpipe every load is a per-lane gather and dominates the cost.
// The includer declares the push constants `p` (NnConvParams) and the output buffer `y` first.

#define CONV_ACC (S4D_NN_CONV_COUT * S4D_NN_CONV_PIX)
// The workgroup's shape: S4D_NN_CONV_WG_X x S4D_NN_CONV_WG_Y, or with S4D_NN_CONV_ROWS (nn_conv1x1_rows,
// for one-row tensors such as a transformer's tokens) S4D_NN_CONV_ROWS_WG_X x 1.
#if defined(S4D_NN_CONV_ROWS) && S4D_NN_CONV_ROWS
#define CONV_WG_X S4D_NN_CONV_ROWS_WG_X
#define CONV_WG_Y 1
#else
#define CONV_WG_X S4D_NN_CONV_WG_X
#define CONV_WG_Y S4D_NN_CONV_WG_Y
#endif

struct ConvTile {
  bool valid;  // some pixel of the strip is inside the image (and the block inside the channels)
  uint x0, y;  // first pixel of the strip
  uint co0;    // first output channel of the block
  uint co[S4D_NN_CONV_COUT];  // channels to read weights for: past cout clamped to the last one
};

ConvTile conv_tile() {
  ConvTile t;
  uint g = flat_group_id(), tiles = p.tiles_x * p.tiles_y, tile = g % tiles;
  t.co0 = (g / tiles) * S4D_NN_CONV_COUT;
  t.x0 = ((tile % p.tiles_x) * CONV_WG_X + gl_LocalInvocationID.x) * S4D_NN_CONV_PIX;
  t.y = (tile / p.tiles_x) * CONV_WG_Y + gl_LocalInvocationID.y;
  t.valid = t.co0 < p.cout && t.x0 < p.width && t.y < p.height;
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) t.co[j] = min(t.co0 + j, p.cout - 1);
  return t;
}

// Writes (or, with S4D_NN_FLAG_ACCUMULATE, adds) acc[j * PIX + k], output channel co0 + j of pixel
// x0 + k, ReLU'd when asked; channels and pixels past the tensor are dropped.
void conv_store(ConvTile t, float acc[CONV_ACC]) {
  uint plane = p.height * p.width, row = t.y * p.width;
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
    [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) {
      if (t.co0 + j >= p.cout || t.x0 + k >= p.width) continue;
      uint i = (t.co0 + j) * plane + row + t.x0 + k;
      float v = (p.flags & S4D_NN_FLAG_ACCUMULATE) != 0u ? y[i] + acc[j * S4D_NN_CONV_PIX + k] : acc[j * S4D_NN_CONV_PIX + k];
      y[i] = (p.flags & S4D_NN_FLAG_RELU) != 0u ? max(v, 0.0) : v;
    }
  }
}
