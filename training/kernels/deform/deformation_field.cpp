// DeformationField: parameter ownership, initialisation and checkpoint transfers. The recording of
// the kernels is in deformation_field_record.cpp.
#include "s4d/deform/deformation_field.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "s4d/deform/field_init.h"
#include "s4d/engine/buffer_from.h"

namespace s4d::deform {

namespace {

uint32_t reg_groups(uint32_t floats) { return (floats + S4D_DEFORM_REG_WG - 1) / S4D_DEFORM_REG_WG; }

}  // namespace

DeformationField::DeformationField(engine::Context& ctx, const FieldConfig& config, uint32_t seed, std::string name,
                                   DeformOptions options)
    : ctx_(&ctx), config_(config), shape_(deform_shape(config)), name_(std::move(name)), options_(options) {
  planes_ = engine::buffer_from(ctx, name_ + " planes", initial_planes(shape_, seed));
  mlp_ = engine::buffer_from(ctx, name_ + " mlp", initial_mlp(shape_, seed));
  v_planes_ = engine::buffer_from(ctx, name_ + " v_planes", std::vector<float>(plane_floats(), 0.0f));
  v_mlp_ = engine::buffer_from(ctx, name_ + " v_mlp", std::vector<float>(mlp_floats(), 0.0f));
  reg_partials_ = engine::Buffer(ctx, name_ + " regulariser partials", size_t{reg_groups(plane_floats())} * 4);
  scratch_ = engine::Buffer(ctx, name_ + " scratch", size_t{scratch_rows()} * gpu::deform_scratch_floats(shape_) * 4);
}

uint32_t DeformationField::scratch_rows() const {
  if (options_.scratch_rows != 0) return options_.scratch_rows;
  const uint32_t row_bytes = gpu::deform_scratch_floats(shape_) * 4;
  const uint32_t rows = S4D_DEFORM_SCRATCH_BYTES / row_bytes / 256 * 256;
  return std::clamp<uint32_t>(rows, 256, S4D_DEFORM_SCRATCH_MAX_ROWS);
}

std::vector<float> DeformationField::download_planes() const { return ctx_->download<float>(planes_, plane_floats()); }

std::vector<float> DeformationField::download_mlp() const { return ctx_->download<float>(mlp_, mlp_floats()); }

void DeformationField::upload_planes(std::span<const float> values) {
  if (values.size() != plane_floats())
    throw std::invalid_argument(name_ + ": upload_planes got " + std::to_string(values.size()) + " floats, the planes hold " +
                                std::to_string(plane_floats()));
  ctx_->upload(planes_, values);
}

void DeformationField::upload_mlp(std::span<const float> values) {
  if (values.size() != mlp_floats())
    throw std::invalid_argument(name_ + ": upload_mlp got " + std::to_string(values.size()) + " floats, the MLP holds " +
                                std::to_string(mlp_floats()));
  ctx_->upload(mlp_, values);
}

double DeformationField::regulariser_value() const {
  double sum = 0;
  for (float v : ctx_->download<float>(reg_partials_, reg_groups(plane_floats()))) sum += v;
  return sum;
}

}  // namespace s4d::deform
