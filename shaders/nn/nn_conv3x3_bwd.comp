// nn_conv3x3_bwd_input: dL/dx of ReflectionPad2d(1) + Conv2d(k=3) (s4d_nn_grad.h). For input pixel
// (r, c) the outputs that read it lie at rows r - 1 .. r + 1 and columns c - 1 .. c + 1; output row
// r - 1 + a reads it through kernel row d when reflect(r - 1 + a + d - 1) = r, which is one tap inside
// the image and up to two at the reflected border rows 1 and h - 2 (likewise for columns). Those 0/1
// coefficients are found once; per output channel the 3x3 neighbourhood of dy is folded into the
// 9 taps' sums G and each of the block's input channels adds its 9 weights times G. The loop over
// output channels is the only runtime loop (llvmpipe's 65,535-iteration cap).
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnConvBwdParams p; };
layout(std430, binding = S4D_B_CONVB_DY) readonly buffer Dy { float dy[]; };
layout(std430, binding = S4D_B_CONVB_WEIGHT) readonly buffer Weight { float weight[]; };
layout(std430, binding = S4D_B_CONVB_DX) buffer Dx { float dx[]; };  // read by S4D_NN_FLAG_ACCUMULATE

// ReflectionPad2d(1): -1 reads 1, n reads n - 2.
int reflect1(int i, int n) { return i < 0 ? -i : (i >= n ? 2 * n - 2 - i : i); }

void main() {
  uint g = flat_group_id(), block = g / p.pixel_groups;
  uint pix = (g % p.pixel_groups) * S4D_NN_WG + gl_LocalInvocationIndex;
  uint ci0 = block * S4D_NN_CONV_COUT, plane = p.height * p.width;
  if (pix >= plane || ci0 >= p.cin) return;
  int r = int(pix / p.width), c = int(pix % p.width), h = int(p.height), w = int(p.width);
  // cy[a][d]: output row r - 1 + a reads row r through kernel row d; likewise cx for columns.
  float cy[3][3], cx[3][3];
  bool row_in[3], col_in[3];
  [[unroll]] for (int a = 0; a < 3; ++a) {
    int o = r - 1 + a, q = c - 1 + a;
    row_in[a] = o >= 0 && o < h;
    col_in[a] = q >= 0 && q < w;
    [[unroll]] for (int d = 0; d < 3; ++d) {
      cy[a][d] = row_in[a] && reflect1(o + d - 1, h) == r ? 1.0 : 0.0;
      cx[a][d] = col_in[a] && reflect1(q + d - 1, w) == c ? 1.0 : 0.0;
    }
  }
  // Reads of neighbours outside the image go to the pixel itself and are weighted 0.
  uint at[3][3];
  [[unroll]] for (int a = 0; a < 3; ++a) {
    [[unroll]] for (int b = 0; b < 3; ++b)
      at[a][b] = row_in[a] && col_in[b] ? uint((r - 1 + a) * w + c - 1 + b) : pix;
  }
  uint ci[S4D_NN_CONV_COUT];
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) ci[j] = min(ci0 + j, p.cin - 1);
  float acc[S4D_NN_CONV_COUT];
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) acc[j] = 0.0;
  for (uint co = 0; co < p.cout; ++co) {
    float nb[3][3];
    [[unroll]] for (int a = 0; a < 3; ++a) {
      [[unroll]] for (int b = 0; b < 3; ++b) nb[a][b] = dy[co * plane + at[a][b]];
    }
    float rows[3][3];  // rows[d][b] = sum_a cy[a][d] nb[a][b]
    [[unroll]] for (int d = 0; d < 3; ++d) {
      [[unroll]] for (int b = 0; b < 3; ++b) rows[d][b] = cy[0][d] * nb[0][b] + cy[1][d] * nb[1][b] + cy[2][d] * nb[2][b];
    }
    float tap[9];  // tap[dy * 3 + dx] = sum_b cx[b][dx] rows[dy][b]
    [[unroll]] for (int d = 0; d < 3; ++d) {
      [[unroll]] for (int e = 0; e < 3; ++e)
        tap[d * 3 + e] = cx[0][e] * rows[d][0] + cx[1][e] * rows[d][1] + cx[2][e] * rows[d][2];
    }
    [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
      uint wi = (co * p.cin + ci[j]) * 9;
      [[unroll]] for (uint t = 0; t < 9; ++t) acc[j] += weight[wi + t] * tap[t];
    }
  }
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
    if (ci0 + j >= p.cin) continue;
    uint i = (ci0 + j) * plane + pix;
    dx[i] = (p.flags & S4D_NN_FLAG_ACCUMULATE) != 0u ? dx[i] + acc[j] : acc[j];
  }
}
