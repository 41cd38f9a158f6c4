#include "s4d/splat/scene_upload.h"

#include <algorithm>

#include "s4d/engine/buffer_from.h"

namespace s4d::splat {

DeviceGaussians::DeviceGaussians(engine::Context& ctx, const io::GaussianCloud& cloud, const std::string& name)
    : count_(static_cast<uint32_t>(cloud.size())), sh_degree_(cloud.sh_degree) {
  const auto arrays = cloud_arrays(cloud);
  for (Attr a : kCloudAttrs) buffers_[a] = engine::buffer_from(ctx, name + " " + attr_name(a), *arrays[a]);
}

GaussianParams DeviceGaussians::params(int sh_degree) const {
  const int degree = sh_degree < 0 ? sh_degree_ : std::min(sh_degree, sh_degree_);
  GaussianParams p{.count = count_,
                   .sh_degree = static_cast<uint32_t>(degree),
                   .sh_coeffs = static_cast<uint32_t>((sh_degree_ + 1) * (sh_degree_ + 1))};
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
