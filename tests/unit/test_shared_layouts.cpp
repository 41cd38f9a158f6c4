// Every struct in shaders/shared/*.h must have the same member names, offsets and sizes in C++ as
// in each compiled shader that uses it, and sizeof must equal the SPIR-V extent (explicit padding).
// Layer (a) is the static_asserts below; layer (b) walks every embedded SPIR-V module.
#include <doctest/doctest.h>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "s4d/engine/spirv_reflect.h"
#include "s4d/shader_registry.h"
#include "s4d_bench.h"
#include "s4d_deform.h"
#include "s4d_densify.h"
#include "s4d_flow.h"
#include "s4d_loss.h"
#include "s4d_nn.h"
#include "s4d_nn_ccpl.h"
#include "s4d_nn_grad.h"
#include "s4d_optim.h"
#include "s4d_primitives.h"
#include "s4d_splat.h"
#include "s4d_style_splat.h"
#include "s4d_viewer.h"

using s4d::engine::CppStructLayout;
using s4d::engine::StructMember;

#define S4D_MEMBER(S, m) StructMember{#m, static_cast<uint32_t>(offsetof(S, m)), static_cast<uint32_t>(sizeof(S::m))}
#define S4D_STRUCT(S, ...) CppStructLayout{#S, static_cast<uint32_t>(sizeof(s4d::gpu::S)), {__VA_ARGS__}}

namespace {

using namespace s4d::gpu;

static_assert(sizeof(ScanParams) == 16 && sizeof(ScanParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(RadixParams) == 16 && sizeof(RadixParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(IotaParams) == 16 && sizeof(IotaParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(SplatCamera) == 80);
static_assert(sizeof(ProjectParams) == 96 && sizeof(ProjectParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(BinningParams) == 16 && sizeof(RasterParams) == 64);
static_assert(sizeof(InstanceArgsParams) == 16 && sizeof(InstanceArgs) == 48);
static_assert(offsetof(InstanceArgs, ranges_groups) == S4D_INSTANCE_ARGS_RANGES_OFFSET &&
              offsetof(InstanceArgs, sort_groups) == S4D_INSTANCE_ARGS_SORT_OFFSET);
static_assert(sizeof(LossParams) == 32 && sizeof(TvParams) == 32 && sizeof(AdamParams) == 32 && sizeof(AdamGroup) == 32);
static_assert(sizeof(AddParams) == 16 && sizeof(MaskParams) == 16);
static_assert(sizeof(BlendCeilingParams) == 48 && sizeof(BlendCeilingParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(DeformShape) == 64);
static_assert(sizeof(DeformParams) == 128 && sizeof(DeformParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(DeformRegParams) == 80 && sizeof(DeformRegParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(DeformWgradParams) == 80 && sizeof(DeformWgradParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(AccumulateParams) == 16 && sizeof(ClassifyParams) == 32 && sizeof(DemoteParams) == 16);
static_assert(sizeof(SlotParams) == 16 && sizeof(SplitParams) == 16);
static_assert(sizeof(FlowProjectParams) == 96 && sizeof(FlowProjectParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(FlowDisplaceParams) == 16);
static_assert(sizeof(PackParams) == 32 && sizeof(PackParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);
static_assert(sizeof(NnConvParams) == 32 && sizeof(NnEltParams) == 16 && sizeof(NnResizeParams) == 32);
static_assert(sizeof(NnConvStridedParams) == 48);
static_assert(sizeof(NnStatsParams) == 16 && sizeof(NnAdainParams) == 16 && sizeof(NnBlendParams) == 16);
static_assert(sizeof(NnAttnParams) == 32);
static_assert(sizeof(NnGroupNormParams) == 48);
static_assert(sizeof(NnWgradParams) == 32 && sizeof(NnWgradReduceParams) == 16);
static_assert(sizeof(NnStatsBwdParams) == 16 && sizeof(NnMseParams) == 16 && sizeof(NnTvL1Params) == 16 && sizeof(NnSelfsimParams) == 16);
static_assert(sizeof(NnCcplParams) == 16 && sizeof(NnPatchNceParams) == 16);
static_assert(sizeof(RasterParams) <= S4D_MAX_PUSH_CONSTANT_BYTES);

// The style MLP's blocks tile its 52 floats in SuperGaussians' order, each on a vec4 boundary (the
// kernels read them as 13 vec4s), and the quadric is whole vec4s with room for Q and b.
static_assert(S4D_STYLE_MLP_W1 == 0 && S4D_STYLE_MLP_B1 == S4D_STYLE_MLP_W1 + 8 &&
              S4D_STYLE_MLP_W2 == S4D_STYLE_MLP_B1 + 4 && S4D_STYLE_MLP_B2 == S4D_STYLE_MLP_W2 + 16 &&
              S4D_STYLE_MLP_W3 == S4D_STYLE_MLP_B2 + 4 && S4D_STYLE_MLP_B3 == S4D_STYLE_MLP_W3 + 16 &&
              S4D_STYLE_MLP_STRIDE == S4D_STYLE_MLP_B3 + 4 && S4D_STYLE_MLP_STRIDE == 52);
static_assert(S4D_STYLE_MLP_STRIDE == 4 * S4D_STYLE_MLP_VEC4S);
static_assert(S4D_STYLE_QUADRIC_B == S4D_STYLE_QUADRIC_Q + 6 && S4D_STYLE_QUADRIC_B + 3 <= S4D_STYLE_QUADRIC_STRIDE &&
              S4D_STYLE_QUADRIC_STRIDE % 4 == 0);
// A style batch in shared memory (raster_batch.glsl: id, xy, conic/opacity, colour/depth, quadric,
// MLP, plus a counter) fits lavapipe's 32 KiB.
static_assert(S4D_STYLE_BATCH * (4 + 8 + 16 + 16 + 4 * S4D_STYLE_QUADRIC_STRIDE + 4 * S4D_STYLE_MLP_STRIDE) + 64 <=
              32768);
// llvmpipe's loop cap, counting each loop's exiting check: 1 + (64 / S4D_STYLE_MARK_UNROLL + 1) +
// (64 / S4D_STYLE_UNROLL + 1) loop iterations per batch at most, forward and backward (the marking
// loop and the walk over the marked slots, raster_walk.glsl), plus one compare-and-swap loop per
// atomic (62 per entry) on the fallback path.
constexpr long kStyleBatchLoops = 3 + S4D_STYLE_BATCH / S4D_STYLE_MARK_UNROLL + S4D_STYLE_BATCH / S4D_STYLE_UNROLL;
static_assert(1 + (S4D_LLVMPIPE_MAX_STYLE_LIST + S4D_STYLE_BATCH - 1) / S4D_STYLE_BATCH * kStyleBatchLoops <= 65535);
static_assert(1 + (S4D_LLVMPIPE_MAX_STYLE_LIST_CAS + S4D_STYLE_BATCH - 1) / S4D_STYLE_BATCH * kStyleBatchLoops +
                  S4D_LLVMPIPE_MAX_STYLE_LIST_CAS * (S4D_STYLE_MLP_STRIDE + S4D_G2D_STRIDE) <=
              65535);

// The C++ side of every shared struct. Adding a struct to a shared header means adding it here;
// a member added in one language only shows up as a member-count mismatch.
std::vector<CppStructLayout> shared_structs() {
  return {
      S4D_STRUCT(ScanParams, S4D_MEMBER(ScanParams, n), S4D_MEMBER(ScanParams, num_blocks),
                 S4D_MEMBER(ScanParams, _pad0), S4D_MEMBER(ScanParams, _pad1)),
      S4D_STRUCT(RadixParams, S4D_MEMBER(RadixParams, n), S4D_MEMBER(RadixParams, shift),
                 S4D_MEMBER(RadixParams, num_blocks), S4D_MEMBER(RadixParams, digit_mask)),
      S4D_STRUCT(IotaParams, S4D_MEMBER(IotaParams, n), S4D_MEMBER(IotaParams, first), S4D_MEMBER(IotaParams, _pad0),
                 S4D_MEMBER(IotaParams, _pad1)),
      S4D_STRUCT(SplatCamera, S4D_MEMBER(SplatCamera, view_row0), S4D_MEMBER(SplatCamera, view_row1),
                 S4D_MEMBER(SplatCamera, view_row2), S4D_MEMBER(SplatCamera, intrinsics), S4D_MEMBER(SplatCamera, size)),
      S4D_STRUCT(ProjectParams, S4D_MEMBER(ProjectParams, cam), S4D_MEMBER(ProjectParams, n),
                 S4D_MEMBER(ProjectParams, sh_degree), S4D_MEMBER(ProjectParams, sh_coeffs),
                 S4D_MEMBER(ProjectParams, flags)),
      S4D_STRUCT(BinningParams, S4D_MEMBER(BinningParams, n), S4D_MEMBER(BinningParams, tiles_x),
                 S4D_MEMBER(BinningParams, capacity), S4D_MEMBER(BinningParams, _pad1)),
      S4D_STRUCT(InstanceArgsParams, S4D_MEMBER(InstanceArgsParams, n), S4D_MEMBER(InstanceArgsParams, capacity),
                 S4D_MEMBER(InstanceArgsParams, max_groups_x), S4D_MEMBER(InstanceArgsParams, _pad0)),
      S4D_STRUCT(InstanceArgs, S4D_MEMBER(InstanceArgs, live), S4D_MEMBER(InstanceArgs, _pad0),
                 S4D_MEMBER(InstanceArgs, _pad1), S4D_MEMBER(InstanceArgs, _pad2),
                 S4D_MEMBER(InstanceArgs, ranges_groups), S4D_MEMBER(InstanceArgs, sort_groups)),
      S4D_STRUCT(RasterParams, S4D_MEMBER(RasterParams, size), S4D_MEMBER(RasterParams, background),
                 S4D_MEMBER(RasterParams, intrinsics), S4D_MEMBER(RasterParams, flags),
                 S4D_MEMBER(RasterParams, depth_mode), S4D_MEMBER(RasterParams, time),
                 S4D_MEMBER(RasterParams, depth_scale)),
      S4D_STRUCT(LossParams, S4D_MEMBER(LossParams, width), S4D_MEMBER(LossParams, height),
                 S4D_MEMBER(LossParams, channels), S4D_MEMBER(LossParams, n), S4D_MEMBER(LossParams, ssim_weight),
                 S4D_MEMBER(LossParams, inv_count), S4D_MEMBER(LossParams, mode), S4D_MEMBER(LossParams, _pad0)),
      S4D_STRUCT(MaskParams, S4D_MEMBER(MaskParams, n), S4D_MEMBER(MaskParams, row), S4D_MEMBER(MaskParams, _pad0),
                 S4D_MEMBER(MaskParams, _pad1)),
      S4D_STRUCT(TvParams, S4D_MEMBER(TvParams, width), S4D_MEMBER(TvParams, height), S4D_MEMBER(TvParams, channels),
                 S4D_MEMBER(TvParams, n), S4D_MEMBER(TvParams, weight), S4D_MEMBER(TvParams, inv_pairs),
                 S4D_MEMBER(TvParams, _pad0), S4D_MEMBER(TvParams, _pad1)),
      S4D_STRUCT(AdamGroup, S4D_MEMBER(AdamGroup, lr), S4D_MEMBER(AdamGroup, beta1), S4D_MEMBER(AdamGroup, beta2),
                 S4D_MEMBER(AdamGroup, eps), S4D_MEMBER(AdamGroup, inv_bias1), S4D_MEMBER(AdamGroup, inv_sqrt_bias2),
                 S4D_MEMBER(AdamGroup, step), S4D_MEMBER(AdamGroup, _pad0)),
      S4D_STRUCT(AdamParams, S4D_MEMBER(AdamParams, n), S4D_MEMBER(AdamParams, group),
                 S4D_MEMBER(AdamParams, tail_group), S4D_MEMBER(AdamParams, row), S4D_MEMBER(AdamParams, head),
                 S4D_MEMBER(AdamParams, _pad0), S4D_MEMBER(AdamParams, _pad1), S4D_MEMBER(AdamParams, _pad2)),
      S4D_STRUCT(AddParams, S4D_MEMBER(AddParams, n), S4D_MEMBER(AddParams, _pad0), S4D_MEMBER(AddParams, _pad1),
                 S4D_MEMBER(AddParams, _pad2)),
      S4D_STRUCT(BlendCeilingParams, S4D_MEMBER(BlendCeilingParams, size), S4D_MEMBER(BlendCeilingParams, background),
                 S4D_MEMBER(BlendCeilingParams, list_length), S4D_MEMBER(BlendCeilingParams, _pad0),
                 S4D_MEMBER(BlendCeilingParams, _pad1), S4D_MEMBER(BlendCeilingParams, _pad2)),
      S4D_STRUCT(DeformShape, S4D_MEMBER(DeformShape, resolution), S4D_MEMBER(DeformShape, multires),
                 S4D_MEMBER(DeformShape, levels), S4D_MEMBER(DeformShape, channels), S4D_MEMBER(DeformShape, width),
                 S4D_MEMBER(DeformShape, trunk_extra), S4D_MEMBER(DeformShape, heads), S4D_MEMBER(DeformShape, _pad0),
                 S4D_MEMBER(DeformShape, _pad1), S4D_MEMBER(DeformShape, _pad2)),
      S4D_STRUCT(DeformParams, S4D_MEMBER(DeformParams, shape), S4D_MEMBER(DeformParams, aabb_max),
                 S4D_MEMBER(DeformParams, aabb_scale), S4D_MEMBER(DeformParams, n), S4D_MEMBER(DeformParams, sh_coeffs),
                 S4D_MEMBER(DeformParams, time), S4D_MEMBER(DeformParams, first), S4D_MEMBER(DeformParams, layer),
                 S4D_MEMBER(DeformParams, layers), S4D_MEMBER(DeformParams, shared_input), S4D_MEMBER(DeformParams, _pad0)),
      S4D_STRUCT(DeformWgradParams, S4D_MEMBER(DeformWgradParams, shape), S4D_MEMBER(DeformWgradParams, rows),
                 S4D_MEMBER(DeformWgradParams, row_floats), S4D_MEMBER(DeformWgradParams, blocks),
                 S4D_MEMBER(DeformWgradParams, _pad0)),
      S4D_STRUCT(DeformRegParams, S4D_MEMBER(DeformRegParams, shape), S4D_MEMBER(DeformRegParams, elements),
                 S4D_MEMBER(DeformRegParams, w_plane_tv), S4D_MEMBER(DeformRegParams, w_time_smoothness),
                 S4D_MEMBER(DeformRegParams, w_l1_time)),
      S4D_STRUCT(AccumulateParams, S4D_MEMBER(AccumulateParams, n), S4D_MEMBER(AccumulateParams, mode),
                 S4D_MEMBER(AccumulateParams, half_width), S4D_MEMBER(AccumulateParams, half_height)),
      S4D_STRUCT(ClassifyParams, S4D_MEMBER(ClassifyParams, n), S4D_MEMBER(ClassifyParams, rules),
                 S4D_MEMBER(ClassifyParams, grad_threshold), S4D_MEMBER(ClassifyParams, log_dense_scale),
                 S4D_MEMBER(ClassifyParams, logit_min_opacity), S4D_MEMBER(ClassifyParams, max_screen_radius),
                 S4D_MEMBER(ClassifyParams, log_max_world_scale), S4D_MEMBER(ClassifyParams, log_split_shrink)),
      S4D_STRUCT(DemoteParams, S4D_MEMBER(DemoteParams, n), S4D_MEMBER(DemoteParams, excess),
                 S4D_MEMBER(DemoteParams, _pad0), S4D_MEMBER(DemoteParams, _pad1)),
      S4D_STRUCT(SlotParams, S4D_MEMBER(SlotParams, n), S4D_MEMBER(SlotParams, width), S4D_MEMBER(SlotParams, zero_new),
                 S4D_MEMBER(SlotParams, value)),
      S4D_STRUCT(SplitParams, S4D_MEMBER(SplitParams, n), S4D_MEMBER(SplitParams, seed),
                 S4D_MEMBER(SplitParams, log_split_shrink), S4D_MEMBER(SplitParams, _pad0)),
      S4D_STRUCT(FlowProjectParams, S4D_MEMBER(FlowProjectParams, cam), S4D_MEMBER(FlowProjectParams, n),
                 S4D_MEMBER(FlowProjectParams, _pad0), S4D_MEMBER(FlowProjectParams, _pad1),
                 S4D_MEMBER(FlowProjectParams, _pad2)),
      S4D_STRUCT(FlowDisplaceParams, S4D_MEMBER(FlowDisplaceParams, n), S4D_MEMBER(FlowDisplaceParams, _pad0),
                 S4D_MEMBER(FlowDisplaceParams, _pad1), S4D_MEMBER(FlowDisplaceParams, _pad2)),
      S4D_STRUCT(PackParams, S4D_MEMBER(PackParams, width), S4D_MEMBER(PackParams, height),
                 S4D_MEMBER(PackParams, src_width), S4D_MEMBER(PackParams, src_height),
                 S4D_MEMBER(PackParams, swap_rb), S4D_MEMBER(PackParams, _pad0), S4D_MEMBER(PackParams, _pad1),
                 S4D_MEMBER(PackParams, _pad2)),
      S4D_STRUCT(NnConvParams, S4D_MEMBER(NnConvParams, cin), S4D_MEMBER(NnConvParams, cout),
                 S4D_MEMBER(NnConvParams, height), S4D_MEMBER(NnConvParams, width), S4D_MEMBER(NnConvParams, tiles_x),
                 S4D_MEMBER(NnConvParams, tiles_y), S4D_MEMBER(NnConvParams, flags), S4D_MEMBER(NnConvParams, _pad0)),
      S4D_STRUCT(NnConvStridedParams, S4D_MEMBER(NnConvStridedParams, cin), S4D_MEMBER(NnConvStridedParams, cout),
                 S4D_MEMBER(NnConvStridedParams, in_height), S4D_MEMBER(NnConvStridedParams, in_width),
                 S4D_MEMBER(NnConvStridedParams, out_height), S4D_MEMBER(NnConvStridedParams, out_width),
                 S4D_MEMBER(NnConvStridedParams, kernel), S4D_MEMBER(NnConvStridedParams, stride),
                 S4D_MEMBER(NnConvStridedParams, pad), S4D_MEMBER(NnConvStridedParams, flags),
                 S4D_MEMBER(NnConvStridedParams, n_out), S4D_MEMBER(NnConvStridedParams, _pad0)),
      S4D_STRUCT(NnEltParams, S4D_MEMBER(NnEltParams, n), S4D_MEMBER(NnEltParams, count), S4D_MEMBER(NnEltParams, _pad0),
                 S4D_MEMBER(NnEltParams, _pad1)),
      S4D_STRUCT(NnResizeParams, S4D_MEMBER(NnResizeParams, channels), S4D_MEMBER(NnResizeParams, in_height),
                 S4D_MEMBER(NnResizeParams, in_width), S4D_MEMBER(NnResizeParams, out_height),
                 S4D_MEMBER(NnResizeParams, out_width), S4D_MEMBER(NnResizeParams, n_out),
                 S4D_MEMBER(NnResizeParams, pad), S4D_MEMBER(NnResizeParams, _pad1)),
      S4D_STRUCT(NnStatsParams, S4D_MEMBER(NnStatsParams, channels), S4D_MEMBER(NnStatsParams, count),
                 S4D_MEMBER(NnStatsParams, eps), S4D_MEMBER(NnStatsParams, _pad0)),
      S4D_STRUCT(NnAdainParams, S4D_MEMBER(NnAdainParams, channels), S4D_MEMBER(NnAdainParams, count),
                 S4D_MEMBER(NnAdainParams, alpha), S4D_MEMBER(NnAdainParams, mode)),
      S4D_STRUCT(NnBlendParams, S4D_MEMBER(NnBlendParams, n), S4D_MEMBER(NnBlendParams, alpha),
                 S4D_MEMBER(NnBlendParams, beta), S4D_MEMBER(NnBlendParams, _pad0)),
      S4D_STRUCT(NnAttnParams, S4D_MEMBER(NnAttnParams, channels), S4D_MEMBER(NnAttnParams, n_c),
                 S4D_MEMBER(NnAttnParams, n_s), S4D_MEMBER(NnAttnParams, first), S4D_MEMBER(NnAttnParams, chunk),
                 S4D_MEMBER(NnAttnParams, _pad0), S4D_MEMBER(NnAttnParams, _pad1), S4D_MEMBER(NnAttnParams, _pad2)),
      S4D_STRUCT(NnGroupNormParams, S4D_MEMBER(NnGroupNormParams, channels), S4D_MEMBER(NnGroupNormParams, groups),
                 S4D_MEMBER(NnGroupNormParams, height), S4D_MEMBER(NnGroupNormParams, width),
                 S4D_MEMBER(NnGroupNormParams, cell_h), S4D_MEMBER(NnGroupNormParams, row0),
                 S4D_MEMBER(NnGroupNormParams, rows), S4D_MEMBER(NnGroupNormParams, col0),
                 S4D_MEMBER(NnGroupNormParams, cols), S4D_MEMBER(NnGroupNormParams, flags),
                 S4D_MEMBER(NnGroupNormParams, eps), S4D_MEMBER(NnGroupNormParams, _pad0)),
      S4D_STRUCT(NnWgradParams, S4D_MEMBER(NnWgradParams, cin), S4D_MEMBER(NnWgradParams, cout), S4D_MEMBER(NnWgradParams, height), S4D_MEMBER(NnWgradParams, width), S4D_MEMBER(NnWgradParams, chunk_rows), S4D_MEMBER(NnWgradParams, chunks), S4D_MEMBER(NnWgradParams, slots), S4D_MEMBER(NnWgradParams, invocations)),
      S4D_STRUCT(NnWgradReduceParams, S4D_MEMBER(NnWgradReduceParams, slots), S4D_MEMBER(NnWgradReduceParams, weights), S4D_MEMBER(NnWgradReduceParams, chunks), S4D_MEMBER(NnWgradReduceParams, flags)),
      S4D_STRUCT(NnStatsBwdParams, S4D_MEMBER(NnStatsBwdParams, channels), S4D_MEMBER(NnStatsBwdParams, count), S4D_MEMBER(NnStatsBwdParams, mode), S4D_MEMBER(NnStatsBwdParams, _pad0)),
      S4D_STRUCT(NnMseParams, S4D_MEMBER(NnMseParams, n), S4D_MEMBER(NnMseParams, scale), S4D_MEMBER(NnMseParams, _pad0), S4D_MEMBER(NnMseParams, _pad1)),
      S4D_STRUCT(NnTvL1Params, S4D_MEMBER(NnTvL1Params, channels), S4D_MEMBER(NnTvL1Params, height), S4D_MEMBER(NnTvL1Params, width), S4D_MEMBER(NnTvL1Params, weight)),
      S4D_STRUCT(NnSelfsimParams, S4D_MEMBER(NnSelfsimParams, channels), S4D_MEMBER(NnSelfsimParams, count), S4D_MEMBER(NnSelfsimParams, weight), S4D_MEMBER(NnSelfsimParams, _pad0)),
      S4D_STRUCT(NnCcplParams, S4D_MEMBER(NnCcplParams, channels), S4D_MEMBER(NnCcplParams, plane), S4D_MEMBER(NnCcplParams, samples), S4D_MEMBER(NnCcplParams, _pad0)),
      S4D_STRUCT(NnPatchNceParams, S4D_MEMBER(NnPatchNceParams, samples), S4D_MEMBER(NnPatchNceParams, inv_tau), S4D_MEMBER(NnPatchNceParams, scale), S4D_MEMBER(NnPatchNceParams, _pad0)),
  };
}

}  // namespace

TEST_CASE("shared structs have identical layouts in C++ and in every shader that uses them") {
  std::map<std::string, int> uses;
  for (const CppStructLayout& cpp : shared_structs()) uses[cpp.name] = 0;
  for (const auto& entry : s4d::shaders::all()) {
    const auto module = s4d::engine::reflect_spirv(entry.spirv(), entry.name);
    for (const CppStructLayout& cpp : shared_structs()) {
      auto [begin, end] = module.structs.equal_range(cpp.name);
      for (auto it = begin; it != end; ++it) {
        ++uses[cpp.name];
        const auto diffs = s4d::engine::compare_layouts(cpp, it->second);
        for (const auto& d : diffs) {
          const std::string message = std::string(entry.name) + ": " + d;
          FAIL_CHECK(message);
        }
      }
    }
  }
  for (const auto& use : uses) CHECK_MESSAGE(use.second > 0, "no shader uses shared struct " << use.first);
}

TEST_CASE("every push-constant block fits the 128-byte guarantee") {
  for (const auto& entry : s4d::shaders::all()) {
    const auto module = s4d::engine::reflect_spirv(entry.spirv(), entry.name);
    CHECK_MESSAGE(module.push_constant_bytes <= S4D_MAX_PUSH_CONSTANT_BYTES, entry.name);
  }
}
