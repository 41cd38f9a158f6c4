#include "s4d/splat/scene_upload.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "s4d/engine/buffer_from.h"
#include "s4d/io/half_float.h"

namespace s4d::splat {

namespace {

// `values` as packed halves; std::invalid_argument naming `name` for a finite value beyond half's range.
std::vector<uint32_t> checked_halves(const std::string& name, std::span<const float> values) {
  for (size_t j = 0; j < values.size(); ++j)
    if (std::isfinite(values[j]) && std::isinf(io::half_to_float(io::float_to_half(values[j]))))
      throw std::invalid_argument(name + ": value " + std::to_string(values[j]) + " at index " + std::to_string(j) +
                                  " is beyond half precision's range (65504); render it in float (without --half)");
  return io::pack_halves(values);
}

}  // namespace

engine::Buffer upload_as(engine::Context& ctx, const std::string& name, std::span<const float> values, Storage storage) {
  if (storage == Storage::f32) return engine::buffer_from(ctx, name, values);
  return engine::buffer_from(ctx, name, checked_halves(name, values));
}

void upload_into(engine::Context& ctx, engine::Buffer& buffer, std::span<const float> values, Storage storage) {
  if (storage == Storage::f32) return ctx.upload(buffer, values);
  const std::vector<uint32_t> words = checked_halves(buffer.name(), values);
  ctx.upload(buffer, std::span<const uint32_t>(words));
}

DeviceGaussians::DeviceGaussians(engine::Context& ctx, const io::GaussianCloud& cloud, const std::string& name,
                                 Storage sh_storage)
    : count_(static_cast<uint32_t>(cloud.size())), sh_degree_(cloud.sh_degree), sh_storage_(sh_storage) {
  const auto arrays = cloud_arrays(cloud);
  for (Attr a : kCloudAttrs)
    buffers_[a] = upload_as(ctx, name + " " + attr_name(a), *arrays[a], a == Attr::sh ? sh_storage : Storage::f32);
}

GaussianParams DeviceGaussians::params(int sh_degree) const {
  const int degree = sh_degree < 0 ? sh_degree_ : std::min(sh_degree, sh_degree_);
  GaussianParams p{.count = count_,
                   .sh_degree = static_cast<uint32_t>(degree),
                   .sh_coeffs = static_cast<uint32_t>((sh_degree_ + 1) * (sh_degree_ + 1)),
                   .sh_storage = sh_storage_};
  for (Attr a : kCloudAttrs) p[a] = &buffers_[a];
  return p;
}

Camera to_splat_camera(const io::CameraView& view) {
  Camera cam;
  for (size_t k = 0; k < 12; ++k) cam.world_to_cam[k] = static_cast<float>(view.world_to_cam[k]);
  cam.fx = static_cast<float>(view.fx), cam.fy = static_cast<float>(view.fy);
  cam.cx = static_cast<float>(view.cx), cam.cy = static_cast<float>(view.cy);
  cam.width = static_cast<uint32_t>(view.width), cam.height = static_cast<uint32_t>(view.height);
  return cam;
}

}  // namespace s4d::splat
