// nn_conv3x3_bwd_input: dL/dx of ReflectionPad2d(1) + Conv2d(k=3) (s4d_nn_grad.h), tiled as the
// forward (nn_conv_tile.glsl): an invocation computes a strip of S4D_NN_CONV_PIX pixels for a block
// of S4D_NN_CONV_COUT input channels, looping over the output channels (the only runtime loop:
// llvmpipe's 65,535-iteration cap). Input pixel (r, c) is read by the outputs at rows r - 1 .. r + 1
// and columns c - 1 .. c + 1; output row r - 1 + a reads it through kernel row d when
// reflect(r - 1 + a + d - 1) = r: one tap inside the image, up to two at the reflected border rows
// 1 and h - 2 (likewise for columns). Those 0/1 coefficients are found once; per output channel the
// dy neighbourhood is folded into each pixel's 9 tap sums, which the block's weights then weigh.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

#define PIX S4D_NN_CONV_PIX

// p.cin: the layer's output channels (looped); p.cout: its input channels (the tile's block).
layout(push_constant) uniform Push { NnConvParams p; };
layout(std430, binding = S4D_B_CONVB_DY) readonly buffer Dy { float dy[]; };
layout(std430, binding = S4D_B_CONVB_WEIGHT) readonly buffer Weight { float weight[]; };
layout(std430, binding = S4D_B_CONVB_DX) buffer Dx { float y[]; };  // read by S4D_NN_FLAG_ACCUMULATE
#include "nn_conv_tile.glsl"

layout(local_size_x = CONV_WG_X, local_size_y = CONV_WG_Y) in;

// ReflectionPad2d(1): -1 reads 1, n reads n - 2.
int reflect1(int i, int n) { return i < 0 ? -i : (i >= n ? 2 * n - 2 - i : i); }

void main() {
  ConvTile t = conv_tile();
  if (!t.valid) return;
  int r = int(t.y), x0 = int(t.x0), h = int(p.height), w = int(p.width);
  // cy[a][d]: output row r - 1 + a reads row r through kernel row d.
  float cy[3][3];
  uint rows[3];
  [[unroll]] for (int a = 0; a < 3; ++a) {
    int o = r - 1 + a;
    bool in_image = o >= 0 && o < h;
    rows[a] = uint(in_image ? o : r) * p.width;  // rows outside are weighted 0
    [[unroll]] for (int d = 0; d < 3; ++d) cy[a][d] = in_image && reflect1(o + d - 1, h) == r ? 1.0 : 0.0;
  }
  // The strip's neighbour columns x0 - 1 .. x0 + PIX; cx[k][b][e]: output column x0 + k - 1 + b reads
  // pixel x0 + k through kernel column e (0 for pixels past the edge, whose outputs are dropped).
  uint cols[PIX + 2];
  [[unroll]] for (int m = 0; m < PIX + 2; ++m) cols[m] = uint(clamp(x0 - 1 + m, 0, w - 1));
  float cx[PIX][3][3];
  [[unroll]] for (int k = 0; k < PIX; ++k) {
    [[unroll]] for (int b = 0; b < 3; ++b) {
      int q = x0 + k - 1 + b;
      bool in_image = x0 + k < w && q >= 0 && q < w;
      [[unroll]] for (int e = 0; e < 3; ++e) cx[k][b][e] = in_image && reflect1(q + e - 1, w) == x0 + k ? 1.0 : 0.0;
    }
  }
  float acc[CONV_ACC];
  [[unroll]] for (uint i = 0; i < CONV_ACC; ++i) acc[i] = 0.0;
  uint plane = p.height * p.width;
  for (uint co = 0; co < p.cin; ++co) {
    float fold[3][PIX + 2];  // fold[d][m] = sum_a cy[a][d] dy[co, r - 1 + a, x0 - 1 + m]
    [[unroll]] for (int m = 0; m < PIX + 2; ++m) {
      float n0 = dy[co * plane + rows[0] + cols[m]], n1 = dy[co * plane + rows[1] + cols[m]],
            n2 = dy[co * plane + rows[2] + cols[m]];
      [[unroll]] for (int d = 0; d < 3; ++d) fold[d][m] = cy[0][d] * n0 + cy[1][d] * n1 + cy[2][d] * n2;
    }
    float tap[PIX][9];  // tap[k][d * 3 + e] = sum_b cx[k][b][e] fold[d][k + b]
    [[unroll]] for (int k = 0; k < PIX; ++k) {
      [[unroll]] for (int d = 0; d < 3; ++d) {
        [[unroll]] for (int e = 0; e < 3; ++e)
          tap[k][d * 3 + e] = cx[k][0][e] * fold[d][k] + cx[k][1][e] * fold[d][k + 1] + cx[k][2][e] * fold[d][k + 2];
      }
    }
    [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
      uint wi = (co * p.cout + t.co[j]) * 9;
      float wt[9];
      [[unroll]] for (uint i = 0; i < 9; ++i) wt[i] = weight[wi + i];
      [[unroll]] for (int k = 0; k < PIX; ++k) {
        float s = 0.0;
        [[unroll]] for (uint i = 0; i < 9; ++i) s += wt[i] * tap[k][i];
        acc[j * PIX + k] += s;
      }
    }
  }
  conv_store(t, acc);
}
