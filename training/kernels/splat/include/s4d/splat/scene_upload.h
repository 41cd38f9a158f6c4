// Bridges from the file formats (s4d_io) to the rasterizer: Gaussians read from a PLY uploaded to
// device buffers, and NeRF-style camera views converted to rasterizer cameras.
#pragma once
#include <span>
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::splat {

// `values` in a new device buffer named `name`, as floats or as packed halves (Storage::f16,
// io::pack_halves). Throws std::invalid_argument naming the buffer, the index and the value when a
// finite value lies beyond half's range (|v| >= 65520 rounds past 65504): the render would read
// infinity there, so it is refused rather than clamped.
engine::Buffer upload_as(engine::Context& ctx, const std::string& name, std::span<const float> values, Storage storage);
// The same into an existing buffer of that size (a restyle reuses its buffers).
void upload_into(engine::Context& ctx, engine::Buffer& buffer, std::span<const float> values, Storage storage);

// A Gaussian cloud resident on the device, in the rasterizer's layouts; the SH as floats or, for
// rendering only, packed halves (`sh_storage`).
class DeviceGaussians {
 public:
  DeviceGaussians(engine::Context& ctx, const io::GaussianCloud& cloud, const std::string& name = "gaussians",
                  Storage sh_storage = Storage::f32);
  // Parameters for the rasterizer at SH degree `sh_degree` (clamped to what the cloud stores;
  // negative: all of it).
  GaussianParams params(int sh_degree = -1) const;
  uint32_t size() const { return count_; }
  // Bytes of device memory in the SH buffer.
  size_t sh_bytes() const { return buffers_[Attr::sh].size(); }

 private:
  PerAttr<engine::Buffer, kCloudAttrCount> buffers_;
  uint32_t count_ = 0;
  int sh_degree_ = 0;
  Storage sh_storage_;
};

Camera to_splat_camera(const io::CameraView& view);

}  // namespace s4d::splat
