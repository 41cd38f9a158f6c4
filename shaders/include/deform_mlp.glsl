// Forward of the deformation MLP for one Gaussian (layout in s4d_deform.h). Needs the push-constant
// block `p` (DeformParams) and the weight buffer `mlp[]` declared before the include.
//
// Every activation of the Gaussian lives in one private array g_act with fixed segments: the
// features, the trunk's pre-activations (one W-segment per trunk layer), the current head's hidden
// pre-activation and its output. Layers read a segment (optionally through ReLU) and write another,
// so one linear_fwd serves every layer; deform_bwd keeps the cotangents in the same layout. The
// segment capacities are specialization constants (S4D_DEFORM_SPEC_*), set by the host to the
// field's sizes; the defaults are the limits of s4d_deform.h.
#ifndef DEFORM_MLP_GLSL
#define DEFORM_MLP_GLSL

layout(constant_id = S4D_DEFORM_SPEC_FEAT) const uint FEAT_CAP = S4D_DEFORM_MAX_FEAT;
layout(constant_id = S4D_DEFORM_SPEC_WIDTH) const uint WIDTH_CAP = S4D_DEFORM_MAX_WIDTH;
layout(constant_id = S4D_DEFORM_SPEC_TRUNK) const uint TRUNK_CAP = S4D_DEFORM_MAX_TRUNK_EXTRA + 1;

#define ACT_FEAT 0u
#define ACT_Z(e) (FEAT_CAP + (e) * WIDTH_CAP)
#define ACT_Y1 (FEAT_CAP + TRUNK_CAP * WIDTH_CAP)
#define ACT_Y2 (ACT_Y1 + WIDTH_CAP)
#define ACT_SIZE (ACT_Y2 + 3u * uint(S4D_DEFORM_SH_COEFFS))

float g_act[ACT_SIZE];

float act_in(uint at, bool relu_in) { return relu_in ? max(g_act[at], 0.0) : g_act[at]; }

// g_act[out_at + o] = bias[o] + sum_i weight[o][i] x[i], x = g_act[in_at ..] (through ReLU if relu_in),
// for the Linear(in_dim -> out_dim) starting at mlp[offset].
void linear_fwd(uint offset, uint in_dim, uint out_dim, uint in_at, bool relu_in, uint out_at) {
  for (uint o = 0u; o < out_dim; ++o) {
    float acc = mlp[offset + out_dim * in_dim + o];
    uint row = offset + o * in_dim;
    for (uint i = 0u; i < in_dim; ++i) acc += mlp[row + i] * act_in(in_at + i, relu_in);
    g_act[out_at + o] = acc;
  }
}

// Trunk: ACT_Z(0) = Linear(F -> W)(features), ACT_Z(e) = Linear(W -> W)(ReLU(ACT_Z(e - 1))).
void trunk_fwd() {
  uint W = p.shape.width;
  linear_fwd(deform_trunk_offset(p.shape, 0u), deform_feat_dim(p.shape), W, ACT_FEAT, false, ACT_Z(0u));
  for (uint e = 1u; e <= p.shape.trunk_extra; ++e)
    linear_fwd(deform_trunk_offset(p.shape, e), W, W, ACT_Z(e - 1u), true, ACT_Z(e));
}

// Head h's first layer: ACT_Y1 = Linear(W -> W)(ReLU(trunk output)).
void head_hidden_fwd(uint h) {
  uint W = p.shape.width;
  linear_fwd(deform_head_offset(p.shape, h), W, W, ACT_Z(p.shape.trunk_extra), true, ACT_Y1);
}

// Head h's output: ACT_Y2 = Linear(W -> out)(ReLU(ACT_Y1)); needs head_hidden_fwd(h) first.
void head_out_fwd(uint h) {
  uint W = p.shape.width;
  linear_fwd(deform_head_offset(p.shape, h) + deform_linear_floats(W, W), W, deform_head_out(h), ACT_Y1, true, ACT_Y2);
}

#endif  // DEFORM_MLP_GLSL
