// Bridges from the file formats (s4d_io) to the rasterizer: Gaussians read from a PLY uploaded to
// device buffers, and NeRF-style camera views converted to rasterizer cameras.
#pragma once
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::splat {

// A Gaussian cloud resident on the device, in the rasterizer's layouts.
class DeviceGaussians {
 public:
  DeviceGaussians(engine::Context& ctx, const io::GaussianCloud& cloud, const std::string& name = "gaussians");
  // Parameters for the rasterizer at SH degree `sh_degree` (clamped to what the cloud stores;
  // negative: all of it).
  GaussianParams params(int sh_degree = -1) const;
  uint32_t size() const { return count_; }

 private:
  PerAttr<engine::Buffer, kCloudAttrCount> buffers_;
  uint32_t count_ = 0;
  int sh_degree_ = 0;
};

Camera to_splat_camera(const io::CameraView& view);

}  // namespace s4d::splat
