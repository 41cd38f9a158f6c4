// Shared layouts of the 4DGaussians deformation field F(x, y, z, t) (ALGORITHMS.md 3.1-3.2): a
// multi-resolution HexPlane feeding a small MLP whose heads offset the canonical Gaussians' raw
// parameters. The kernels (shaders/deform), the host class (training/kernels/deform) and the CPU twin
// (training/ref/include/s4d/ref/hexplane_ref.h, deform_mlp_ref.h, deform_ref.h) all take the plane
// and weight offsets from the functions below, so there is one definition of both layouts.
//
// Planes. Plane p pairs coordinates (u, v) = (S4D_DEFORM_PLANE_AXIS_U(p), S4D_DEFORM_PLANE_AXIS_V(p))
// of (x, y, z, t) = (0, 1, 2, 3), in 4DGaussians' order 0 = xy, 1 = xz, 2 = xt, 3 = yz, 4 = yt, 5 = zt.
// Width indexes u, height indexes v (PyTorch's [1, C, R_v, R_u]). Level l has spatial resolution
// resolution.xyz * multires[l]; the time resolution resolution.w is not multiplied. Storage, one flat
// float buffer: level-major, then plane 0..5, each plane [R_v, R_u, C] with the C channels innermost
// (one contiguous read per texel; PyTorch's channel-first planes need a transpose on import).
//
// Lookup of a point (x, y, z) at time t (4DGaussians' mapping, kept bit-for-bit so its checkpoints
// read correctly): u_k = (p_k - aabb_max_k) * (2 / (aabb_min_k - aabb_max_k)) - 1 for k = x, y, z (the
// AABB maps max to -1 and min to +1: mirrored), and the time coordinate is DeformParams::time, the
// host's grid coordinate of the camera's time (deform::grid_time over the field's time range; t
// itself for 4DGaussians' range [-1, 1], where t in [0, 1) uses only the upper half of the time
// axis). Texel coordinate (align_corners = True)
// i = (u + 1) / 2 * (R - 1), clamped to [0, R - 1] (border padding); bilinear weights. Within a
// level the 6 sampled C-vectors multiply element-wise; levels concatenate: feat[l * C + c].
//
// MLP, one flat float buffer; every Linear(in -> out) is its weight [out, in] row-major (PyTorch's
// layout) followed by its bias [out]:
//   trunk: Linear(F -> W), then trunk_extra x [ReLU, Linear(W -> W)]; no activation after it.
//          F = C * levels. 4DGaussians' defor_depth D gives trunk_extra = max(D - 1, 0).
//   heads, in the order pos, scales, rotations, opacity, sh, only those set in `heads`: each
//          ReLU -> Linear(W -> W) -> ReLU -> Linear(W -> out) on the trunk output.
// Head outputs add to the raw parameters: means += pos, log_scales += scales, quats (w, x, y, z) +=
// rotations, opacity logit += opacity, sh[k * 3 + c] += sh head (16 coefficients x 3, coefficient-major).
#ifndef S4D_DEFORM_H
#define S4D_DEFORM_H
#include "s4d_common.h"

#ifdef __cplusplus
#define S4D_DEFORM_FN inline constexpr
#else
#define S4D_DEFORM_FN
#endif

#define S4D_DEFORM_PLANES 6
// Plane p's axes packed 4 bits per plane: u in bits 0-1, v in bits 2-3 (xy, xz, xt, yz, yt, zt).
#define S4D_DEFORM_PLANE_AXES 0xED9C84u
#define S4D_DEFORM_PLANE_AXIS_U(p) ((S4D_DEFORM_PLANE_AXES >> (4u * (p))) & 3u)
#define S4D_DEFORM_PLANE_AXIS_V(p) ((S4D_DEFORM_PLANE_AXES >> (4u * (p) + 2u)) & 3u)
#define S4D_DEFORM_TIME_AXIS 3u  // a plane whose v axis is time is a time plane (xt, yt, zt)

// Heads (bits of DeformShape.heads) and their output sizes.
#define S4D_DEFORM_HEADS 5
#define S4D_DEFORM_HEAD_POS 1u
#define S4D_DEFORM_HEAD_SCALES 2u
#define S4D_DEFORM_HEAD_ROTATIONS 4u
#define S4D_DEFORM_HEAD_OPACITY 8u
#define S4D_DEFORM_HEAD_SH 16u
#define S4D_DEFORM_HEADS_DNERF 7u    // dx, ds, dr (4DGaussians' no_do = no_dshs = True)
#define S4D_DEFORM_HEADS_DYNERF 31u  // dx, ds, dr, do, dshs (the DyNeRF config)
#define S4D_DEFORM_SH_COEFFS 16      // the sh head deforms all 16 degree-3 coefficients

// Limits of the field's shape. 4DGaussians uses C 16/32, 2 levels, W 64/128 and no extra trunk layer.
// No kernel's loop count grows with the MLP's size past one layer (llvmpipe ends an invocation after
// 65535 loop iterations in total): the widest loop is deform_bwd's sum over the heads' hidden
// layers, S4D_DEFORM_HEADS x W iterations.
#define S4D_DEFORM_MAX_LEVELS 4        // multires is a uvec4
#define S4D_DEFORM_MAX_CHANNELS 32
#define S4D_DEFORM_MAX_FEAT 128        // C * levels
#define S4D_DEFORM_MAX_WIDTH 128
#define S4D_DEFORM_MAX_TRUNK_EXTRA 3
#define S4D_DEFORM_MIN_RESOLUTION 3    // bilinear needs 2 texels, the second difference 3

// Specialization constant of deform_feat_bwd: the capacity of its private plane samples, set by the
// host to the field's C (a smaller array compiles faster and spills less); the default is the limit.
#define S4D_DEFORM_SPEC_CHANNELS 0   // >= C

// The MLP runs one Linear layer set per dispatch over a pass of up to scratch-rows Gaussians, whose
// activations and cotangents live in the scratch rows (layout below, "Scratch row"):
//   deform_feat      one invocation per Gaussian: the HexPlane features;
//   deform_fwd       a layer set's outputs: a workgroup is S4D_DEFORM_TILE Gaussians (S4D_DEFORM_ROWS
//                    per invocation) x S4D_DEFORM_BLOCK outputs of one layer, so the weights it
//                    reads are the same for the whole workgroup, and each weight and input read
//                    serves 4 multiply-adds (on llvmpipe a storage-buffer read inside a loop costs
//                    one scalar load per lane); the heads' output layers write the deformed parameters;
//   deform_cot       one invocation per Gaussian: the heads' output cotangents into the rows;
//   deform_bwd       a layer set's input cotangents, blocks of S4D_DEFORM_BLOCK inputs;
//   deform_feat_bwd  one invocation per Gaussian: plane gradients (atomic scatter) and dL/d mean;
//   deform_wgrad     the weight gradients from the rows: one invocation per 4x4 weight block and
//                    S4D_DEFORM_WGRAD_ROWS rows, one atomic add per weight and invocation.
// Layer sets (deform_set_blocks): one trunk layer, or the hidden layers of all heads that are on
// (which share the trunk output as input, so their input cotangents sum), or their output layers.
// No kernel has a barrier: on lavapipe a barrier in a kernel with private state costs more than the
// arithmetic; the host puts a pipeline barrier between dispatches.
#define S4D_DEFORM_WG 64               // invocations per workgroup of deform_feat / _fwd / _cot / _bwd / _feat_bwd
#define S4D_DEFORM_BLOCK 4             // outputs (deform_fwd) or inputs (deform_bwd) per invocation
#define S4D_DEFORM_ROWS 4              // Gaussians per invocation of deform_fwd / deform_bwd
#define S4D_DEFORM_TILE (S4D_DEFORM_WG * S4D_DEFORM_ROWS)  // Gaussians per workgroup of deform_fwd / deform_bwd
#define S4D_DEFORM_REG_WG 256          // deform_reg: one invocation per plane element
#define S4D_DEFORM_WGRAD_WG 64
#define S4D_DEFORM_WGRAD_ROWS 256
// Scratch rows (Gaussians) per pass: at most this many bytes of scratch, a multiple of 256 rows, at
// most S4D_DEFORM_SCRATCH_MAX_ROWS; more Gaussians take more passes.
#define S4D_DEFORM_SCRATCH_BYTES (32u * 1024u * 1024u)
#define S4D_DEFORM_SCRATCH_MAX_ROWS 65536u

// deform_feat bindings.
#define S4D_B_DFEAT_PLANES 0          // [plane floats] f32
#define S4D_B_DFEAT_MEANS 1           // [N, 3] canonical
#define S4D_B_DFEAT_SCRATCH 2         // [rows, deform_scratch_floats] f32 out: the features

// deform_fwd bindings. Per-Gaussian arrays are flat floats (s4d_splat.h layouts).
#define S4D_B_DFWD_MLP 0              // [mlp floats] f32
#define S4D_B_DFWD_SCRATCH 1          // [rows, deform_scratch_floats] in: the set's inputs; out: its activations
#define S4D_B_DFWD_MEANS 2            // [N, 3] canonical
#define S4D_B_DFWD_LOG_SCALES 3       // [N, 3]
#define S4D_B_DFWD_QUATS 4            // [N, 4] (w, x, y, z)
#define S4D_B_DFWD_OPACITY_LOGITS 5   // [N]
#define S4D_B_DFWD_SH 6               // [N, K, 3], K = sh_coeffs
#define S4D_B_DFWD_OUT_MEANS 7        // deformed outputs, same layouts; written by the heads' output layers
#define S4D_B_DFWD_OUT_LOG_SCALES 8
#define S4D_B_DFWD_OUT_QUATS 9
#define S4D_B_DFWD_OUT_OPACITY_LOGITS 10
#define S4D_B_DFWD_OUT_SH 11

// deform_cot bindings.
#define S4D_B_DCOT_V_MEANS 0          // [N, 3] dL/d deformed means
#define S4D_B_DCOT_V_LOG_SCALES 1     // [N, 3]
#define S4D_B_DCOT_V_QUATS 2          // [N, 4]
#define S4D_B_DCOT_V_OPACITY_LOGITS 3 // [N]
#define S4D_B_DCOT_V_SH 4             // [N, K, 3]
#define S4D_B_DCOT_SCRATCH 5          // [rows, deform_scratch_floats] out: the head-output cotangents

// deform_bwd bindings.
#define S4D_B_DBWD_MLP 0
#define S4D_B_DBWD_SCRATCH 1          // [rows, deform_scratch_floats] in: activations, output cotangents; out: input cotangents

// deform_feat_bwd bindings.
#define S4D_B_DFB_PLANES 0
#define S4D_B_DFB_MEANS 1             // [N, 3] canonical
#define S4D_B_DFB_V_MEANS 2           // [N, 3] in: dL/d deformed means; out: dL/d canonical means
#define S4D_B_DFB_V_PLANES 3          // [plane floats] accumulated (+=) with atomics
#define S4D_B_DFB_SCRATCH 4           // [rows, deform_scratch_floats] in: dL/d features

// deform_wgrad bindings.
#define S4D_B_DWG_SCRATCH 0           // [rows, deform_scratch_floats] f32, written by deform_fwd and deform_bwd
#define S4D_B_DWG_V_MLP 1             // [mlp floats] accumulated (+=) with atomics

// deform_reg bindings.
#define S4D_B_DREG_PLANES 0
#define S4D_B_DREG_V_PLANES 1         // [plane floats] accumulated (+=), one invocation per element: no atomics
#define S4D_B_DREG_PARTIALS 2         // [workgroups] f32 weighted regulariser sum of each workgroup

S4D_NAMESPACE_BEGIN

// The field's shape: plane resolutions, channels and MLP sizes.
struct DeformShape {
  uvec4 resolution;  // base (R_x, R_y, R_z, R_t), each >= S4D_DEFORM_MIN_RESOLUTION
  uvec4 multires;    // spatial multiplier of each level; entries past `levels` unused
  uint levels;       // 1..S4D_DEFORM_MAX_LEVELS
  uint channels;     // C per plane
  uint width;        // W of the MLP
  uint trunk_extra;  // extra [ReLU, Linear(W -> W)] trunk layers
  uint heads;        // S4D_DEFORM_HEAD_* bits
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

// Push constants of deform_feat, deform_fwd, deform_bwd and deform_feat_bwd.
struct DeformParams {
  DeformShape shape;
  vec4 aabb_max;    // xyz: the AABB's max corner (4DGaussians' aabb[0]); w unused
  vec4 aabb_scale;  // xyz: 2 / (aabb_min - aabb_max), computed in float on the host; w unused
  uint n;           // end of the Gaussians deformed: the moving prefix (still ones follow; the host copies them)
  uint sh_coeffs;   // K stored per Gaussian and channel; S4D_DEFORM_SH_COEFFS when the sh head is on
  float time;       // the fourth grid coordinate (deform::grid_time of the camera's time)
  uint first;       // first Gaussian of this pass (scratch row 0); the pass covers Gaussians first..n-1
  uint layer;       // deform_fwd / deform_bwd: the set's first layer; the others follow every second layer
  uint layers;      // layers in the set
  uint shared_input;  // deform_bwd: 1 when the set's layers share their input (the heads' hidden layers)
  uint _pad0;
};

// Push constants of deform_wgrad.
struct DeformWgradParams {
  DeformShape shape;
  uint rows;        // scratch rows (Gaussians) written by the deform_bwd pass
  uint row_floats;  // deform_scratch_floats(shape)
  uint blocks;      // deform_wgrad_blocks(shape): 4x4 weight blocks over all layers
  uint _pad0;
};

// Push constants of deform_reg. Weights as ALGORITHMS.md 3.2: plane_tv on the spatial planes'
// smoothness, time_smoothness on the time planes', l1_time on mean |1 - P| of the time planes.
struct DeformRegParams {
  DeformShape shape;
  uint elements;    // plane floats in total
  float w_plane_tv;
  float w_time_smoothness;
  float w_l1_time;
};

// Resolution of axis (0 x, 1 y, 2 z, 3 t) at a level.
S4D_DEFORM_FN uint deform_axis_res(DeformShape s, uint level, uint axis) {
  uint m = level == 0u ? s.multires.x : level == 1u ? s.multires.y : level == 2u ? s.multires.z : s.multires.w;
  return axis == 0u ? s.resolution.x * m : axis == 1u ? s.resolution.y * m : axis == 2u ? s.resolution.z * m
                                                                                        : s.resolution.w;
}

S4D_DEFORM_FN uint deform_plane_floats(DeformShape s, uint level, uint plane) {
  return deform_axis_res(s, level, S4D_DEFORM_PLANE_AXIS_U(plane)) *
         deform_axis_res(s, level, S4D_DEFORM_PLANE_AXIS_V(plane)) * s.channels;
}

// First float of (level, plane) in the plane buffer; (s.levels, 0) gives the total.
S4D_DEFORM_FN uint deform_plane_offset(DeformShape s, uint level, uint plane) {
  uint offset = 0u;
  for (uint k = 0u; k < level * uint(S4D_DEFORM_PLANES) + plane; ++k)
    offset += deform_plane_floats(s, k / uint(S4D_DEFORM_PLANES), k % uint(S4D_DEFORM_PLANES));
  return offset;
}

S4D_DEFORM_FN uint deform_planes_total(DeformShape s) { return deform_plane_offset(s, s.levels, 0u); }

S4D_DEFORM_FN uint deform_feat_dim(DeformShape s) { return s.channels * s.levels; }

// Output size of head h (0 pos, 1 scales, 2 rotations, 3 opacity, 4 sh).
S4D_DEFORM_FN uint deform_head_out(uint h) {
  return h == 0u ? 3u : h == 1u ? 3u : h == 2u ? 4u : h == 3u ? 1u : 3u * uint(S4D_DEFORM_SH_COEFFS);
}

S4D_DEFORM_FN bool deform_head_on(DeformShape s, uint h) { return ((s.heads >> h) & 1u) != 0u; }

// Floats of one Linear(in -> out): weight then bias.
S4D_DEFORM_FN uint deform_linear_floats(uint in_dim, uint out_dim) { return out_dim * in_dim + out_dim; }

// First float of trunk layer e (0: Linear(F -> W); 1..trunk_extra: Linear(W -> W)).
S4D_DEFORM_FN uint deform_trunk_offset(DeformShape s, uint e) {
  return e == 0u ? 0u
                 : deform_linear_floats(deform_feat_dim(s), s.width) + (e - 1u) * deform_linear_floats(s.width, s.width);
}

S4D_DEFORM_FN uint deform_head_floats(DeformShape s, uint h) {
  return deform_linear_floats(s.width, s.width) + deform_linear_floats(s.width, deform_head_out(h));
}

// First float of head h's first layer (its second follows at + deform_linear_floats(W, W)); for a
// head that is off, where it would start. h = S4D_DEFORM_HEADS gives the MLP's total.
S4D_DEFORM_FN uint deform_head_offset(DeformShape s, uint h) {
  uint offset = deform_trunk_offset(s, s.trunk_extra + 1u);
  for (uint k = 0u; k < h; ++k)
    if (deform_head_on(s, k)) offset += deform_head_floats(s, k);
  return offset;
}

S4D_DEFORM_FN uint deform_mlp_total(DeformShape s) { return deform_head_offset(s, uint(S4D_DEFORM_HEADS)); }

// The MLP's Linear layers in scratch order: 0..trunk_extra the trunk, then for each head that is on
// its hidden layer (W -> W) and its output layer (W -> out).
S4D_DEFORM_FN uint deform_layer_count(DeformShape s) {
  uint on = 0u;
  for (uint h = 0u; h < uint(S4D_DEFORM_HEADS); ++h)
    if (deform_head_on(s, h)) ++on;
  return s.trunk_extra + 1u + 2u * on;
}

// Head of a head layer l (> trunk_extra).
S4D_DEFORM_FN uint deform_layer_head(DeformShape s, uint l) {
  uint pair = (l - s.trunk_extra - 1u) / 2u, h = 0u;
  for (uint k = 0u; k < uint(S4D_DEFORM_HEADS); ++k)
    if (deform_head_on(s, k)) {
      if (pair == 0u) {
        h = k;
        break;
      }
      --pair;
    }
  return h;
}

S4D_DEFORM_FN bool deform_layer_is_head_out(DeformShape s, uint l) {
  return l > s.trunk_extra && (l - s.trunk_extra - 1u) % 2u == 1u;
}

S4D_DEFORM_FN uint deform_layer_in(DeformShape s, uint l) { return l == 0u ? deform_feat_dim(s) : s.width; }

S4D_DEFORM_FN uint deform_layer_out(DeformShape s, uint l) {
  return deform_layer_is_head_out(s, l) ? deform_head_out(deform_layer_head(s, l)) : s.width;
}

// First float of layer l in the MLP buffer.
S4D_DEFORM_FN uint deform_layer_offset(DeformShape s, uint l) {
  if (l <= s.trunk_extra) return deform_trunk_offset(s, l);
  return deform_head_offset(s, deform_layer_head(s, l)) +
         (deform_layer_is_head_out(s, l) ? deform_linear_floats(s.width, s.width) : 0u);
}

// Scratch row of one Gaussian, in columns:
//   feat [F]                      the HexPlane features (deform_feat)
//   act slot 0..trunk_extra [W]   ReLU(z_e) of trunk layer e's output z_e (deform_fwd)
//   act slot trunk_extra + 1 + k  ReLU(y_k) of the k-th head on's hidden output y_k (deform_fwd)
//   cot slot 0.. [W]              dL/d z_e and dL/d y_k, same slots (deform_bwd)
//   head outs                     dL/d each head on's output, packed in head order (deform_cot)
//   v_feat [F]                    dL/d feat (deform_bwd), read by deform_feat_bwd
// Every consumer of z_e or y_k goes through a ReLU, so the activations are stored after it, and a
// pre-activation is positive exactly where its stored activation is: that is the ReLU's derivative.
S4D_DEFORM_FN uint deform_slots(DeformShape s) { return deform_layer_count(s) - (deform_layer_count(s) - s.trunk_extra - 1u) / 2u; }

S4D_DEFORM_FN uint deform_act_col(DeformShape s, uint slot) { return deform_feat_dim(s) + slot * s.width; }

S4D_DEFORM_FN uint deform_cot_col(DeformShape s, uint slot) { return deform_act_col(s, deform_slots(s) + slot); }

// Floats of the outputs of the heads that are on before head h (S4D_DEFORM_HEADS: all of them).
S4D_DEFORM_FN uint deform_head_outs_before(DeformShape s, uint h) {
  uint n = 0u;
  for (uint k = 0u; k < h; ++k)
    if (deform_head_on(s, k)) n += deform_head_out(k);
  return n;
}

// First column of dL/d head output of layer l (a head's output layer).
S4D_DEFORM_FN uint deform_head_out_col(DeformShape s, uint l) {
  return deform_cot_col(s, deform_slots(s)) + deform_head_outs_before(s, deform_layer_head(s, l));
}

S4D_DEFORM_FN uint deform_v_feat_col(DeformShape s) {
  return deform_cot_col(s, deform_slots(s)) + deform_head_outs_before(s, uint(S4D_DEFORM_HEADS));
}

// The slot of layer l's output (not for a head's output layer) and of its input (l > 0).
S4D_DEFORM_FN uint deform_out_slot(DeformShape s, uint l) { return l <= s.trunk_extra ? l : s.trunk_extra + 1u + (l - s.trunk_extra - 1u) / 2u; }

S4D_DEFORM_FN uint deform_in_slot(DeformShape s, uint l) {
  return l <= s.trunk_extra ? l - 1u : deform_layer_is_head_out(s, l) ? deform_out_slot(s, l) : s.trunk_extra;
}

// Columns of layer l's input (after its ReLU), of dL/d its input's pre-activation, and of dL/d its output.
S4D_DEFORM_FN uint deform_in_col(DeformShape s, uint l) { return l == 0u ? 0u : deform_act_col(s, deform_in_slot(s, l)); }

S4D_DEFORM_FN uint deform_v_in_col(DeformShape s, uint l) {
  return l == 0u ? deform_v_feat_col(s) : deform_cot_col(s, deform_in_slot(s, l));
}

S4D_DEFORM_FN uint deform_v_out_col(DeformShape s, uint l) {
  return deform_layer_is_head_out(s, l) ? deform_head_out_col(s, l) : deform_cot_col(s, deform_out_slot(s, l));
}

S4D_DEFORM_FN uint deform_scratch_floats(DeformShape s) { return deform_v_feat_col(s) + deform_feat_dim(s); }

// Blocks of S4D_DEFORM_BLOCK outputs (deform_fwd) or inputs (deform_bwd) of the layer set
// {layer, layer + 2, ...} of `layers` layers; deform_bwd with shared_input covers the first
// layer's input once.
S4D_DEFORM_FN uint deform_set_blocks(DeformShape s, uint layer, uint layers, bool backward, bool shared_input) {
  uint b = 0u;
  for (uint k = 0u; k < (shared_input ? 1u : layers); ++k) {
    uint l = layer + 2u * k;
    b += ((backward ? deform_layer_in(s, l) : deform_layer_out(s, l)) + uint(S4D_DEFORM_BLOCK) - 1u) / uint(S4D_DEFORM_BLOCK);
  }
  return b;
}

// deform_wgrad's 4x4 weight blocks of layer l (outputs x inputs, partial blocks at the edges).
S4D_DEFORM_FN uint deform_layer_blocks(DeformShape s, uint l) {
  return (deform_layer_out(s, l) + 3u) / 4u * ((deform_layer_in(s, l) + 3u) / 4u);
}

S4D_DEFORM_FN uint deform_wgrad_blocks(DeformShape s) {
  uint b = 0u;
  for (uint l = 0u; l < deform_layer_count(s); ++l) b += deform_layer_blocks(s, l);
  return b;
}

S4D_NAMESPACE_END

#endif  // S4D_DEFORM_H
