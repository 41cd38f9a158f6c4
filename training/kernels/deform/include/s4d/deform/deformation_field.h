// The 4DGaussians deformation field F(x, y, z, t) on the GPU (ALGORITHMS.md 3.1-3.2): owns the
// HexPlane and MLP parameters and their gradients, and records the kernels of shaders/deform
// (deform_feat, deform_fwd, deform_bwd, deform_feat_bwd + deform_wgrad or their _cas variants,
// deform_reg). Layouts: shaders/shared/s4d_deform.h.
// CPU twin: training/ref/include/s4d/ref/deform_ref.h and hexplane_reg_ref.h.
//
// Every record_* only records: the caller orders dependent work with Recorder::barrier() and
// submits. Gradients accumulate (+=) over record_backward / record_regularisers calls until
// record_zero_grads, so the views of a batch can share one optimizer step.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "s4d/deform/field_config.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/splat/gaussian_buffers.h"
#include "s4d_deform.h"

namespace s4d::deform {

// Canonical (undeformed) Gaussians, one buffer per attribute (s4d/splat/gaussian_buffers.h). `means`
// is always read; the other cloud attributes only when their head is on (they may be null
// otherwise). The last `still_count` Gaussians are still ("deform only what moves", motion_split.h
// puts them last): the field skips them, so their deformed values are copies of the canonical ones
// and they feed the field no gradient.
//
// Deformed outputs (record_forward) are a splat::GaussianBuffers<engine::Buffer> in the same
// layouts, written only for heads that are on (others may be null: use the canonical buffer there).
// Cotangents of the deformed parameters (record_backward) are the rasterizer's splat::GaussianGrads:
// [means] is updated in place to dL/d canonical means; the other canonical gradients equal the
// deformed ones (deformed = canonical + delta) and are only read, for heads that are on.
struct CanonicalGaussians {
  splat::GaussianBuffers<const engine::Buffer> buffers;
  uint32_t count = 0;
  uint32_t still_count = 0;  // <= count
  uint32_t sh_coeffs = 0;  // K; must be S4D_DEFORM_SH_COEFFS when the sh head is on
  // The SH as packed halves (a trained model's render-side storage) are read by the forward only.
  splat::Storage sh_storage = splat::Storage::f32;

  const engine::Buffer*& operator[](splat::Attr a) { return buffers[a]; }
  const engine::Buffer* operator[](splat::Attr a) const { return buffers[a]; }
};

// The field's heads are the cloud's attributes in order: head h deforms splat::kCloudAttrs[h].
static_assert(S4D_DEFORM_HEADS == splat::kCloudAttrCount);

// ALGORITHMS.md 3.2 weights (D-NeRF: 1e-4, 1e-2, 1e-4; DyNeRF: 2e-4, 1e-3, 1e-4).
struct RegulariserWeights {
  float plane_tv = 0, time_smoothness = 0, l1_time_planes = 0;
};

struct DeformOptions {
  bool force_cas_atomics = false;  // use deform_feat_bwd_cas / deform_wgrad_cas even where float atomics exist
  uint32_t scratch_rows = 0;       // Gaussians per forward or backward pass; 0: as many as S4D_DEFORM_SCRATCH_BYTES hold
};

class DeformationField {
 public:
  // Allocates and initialises the parameters (field_init.h, from `seed`) and zeroes the gradients.
  // Throws std::invalid_argument naming the offending configuration field.
  DeformationField(engine::Context& ctx, const FieldConfig& config, uint32_t seed, std::string name = "deform",
                   DeformOptions options = {});

  const FieldConfig& config() const { return config_; }
  const gpu::DeformShape& shape() const { return shape_; }

  // Parameters and gradients, one buffer each for the planes and the MLP (separate Adam groups:
  // grid_lr vs deformation_lr). Offsets inside them: s4d_deform.h.
  engine::Buffer& planes() { return planes_; }
  engine::Buffer& mlp() { return mlp_; }
  const engine::Buffer& planes() const { return planes_; }
  const engine::Buffer& mlp() const { return mlp_; }
  engine::Buffer& v_planes() { return v_planes_; }
  engine::Buffer& v_mlp() { return v_mlp_; }
  const engine::Buffer& v_planes() const { return v_planes_; }
  const engine::Buffer& v_mlp() const { return v_mlp_; }
  uint32_t plane_floats() const { return gpu::deform_planes_total(shape_); }
  uint32_t mlp_floats() const { return gpu::deform_mlp_total(shape_); }
  // Gaussians per forward or backward pass (the scratch buffer's rows; s4d_deform.h).
  uint32_t scratch_rows() const;

  // Checkpoints: whole parameter arrays (waits for submitted work). Uploads check the size.
  std::vector<float> download_planes() const;
  std::vector<float> download_mlp() const;
  void upload_planes(std::span<const float> values);
  void upload_mlp(std::span<const float> values);

  void record_zero_grads(engine::Recorder& rec) const;
  // Deformed parameters at time `time` (the camera's; the kernels get grid_time of it): per
  // scratch_rows() moving Gaussians deform_feat and deform_fwd's layer sets, with barriers before
  // and between them (they share the scratch buffer); buffer copies of the still ones.
  void record_forward(engine::Recorder& rec, const CanonicalGaussians& g, float time,
                      const splat::GaussianBuffers<engine::Buffer>& out) const;
  // Backward of record_forward with the same g and time: adds to v_planes() and v_mlp(), updates v[means].
  // Records, per scratch_rows() moving Gaussians, the forward's activations again (deform_feat,
  // deform_fwd), deform_bwd's layer sets back to the features, then deform_feat_bwd and
  // deform_wgrad, with barriers before, between and after them; still Gaussians' cotangents are
  // left as they are (dL/d canonical = dL/d deformed).
  void record_backward(engine::Recorder& rec, const CanonicalGaussians& g, float time,
                       const splat::GaussianGrads& v) const;
  // Adds the regularisers' gradient to v_planes(); their value is regulariser_value() once run.
  void record_regularisers(engine::Recorder& rec, const RegulariserWeights& w) const;
  // R of the last recorded record_regularisers, after its submission completed (waits, downloads).
  double regulariser_value() const;

 private:
  gpu::DeformParams params(const CanonicalGaussians& g, float time) const;
  void check_gaussians(const CanonicalGaussians& g) const;
  uint32_t heads_on() const;
  void record_mlp_forward(engine::Recorder& rec, gpu::DeformParams p, const CanonicalGaussians& g,
                          const splat::GaussianBuffers<engine::Buffer>* outputs) const;

  engine::Context* ctx_;
  FieldConfig config_;
  gpu::DeformShape shape_;
  std::string name_;
  DeformOptions options_;
  engine::Buffer planes_, mlp_, v_planes_, v_mlp_, reg_partials_;
  engine::Buffer scratch_;  // one pass's activations and cotangents: [scratch_rows(), deform_scratch_floats] f32
};

}  // namespace s4d::deform
