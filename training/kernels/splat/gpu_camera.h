// The kernels' camera block (gpu::SplatCamera, shaders/shared/s4d_splat.h) of a rasterizer camera;
// shared by the rasterizer and the exact-flow op so both project identically. Private to s4d_splat.
#pragma once
#include "s4d/primitives/shader_pipeline.h"
#include "s4d/splat/rasterizer.h"
#include "s4d_splat.h"

namespace s4d::splat {

inline gpu::SplatCamera gpu_camera(const Camera& cam) {
  const auto& V = cam.world_to_cam;
  gpu::SplatCamera c{};
  c.view_row0 = {V[0], V[1], V[2], V[3]};
  c.view_row1 = {V[4], V[5], V[6], V[7]};
  c.view_row2 = {V[8], V[9], V[10], V[11]};
  c.intrinsics = {cam.fx, cam.fy, cam.cx, cam.cy};
  c.size = {cam.width, cam.height, primitives::ceil_div(cam.width, S4D_TILE_SIZE),
            primitives::ceil_div(cam.height, S4D_TILE_SIZE)};
  return c;
}

}  // namespace s4d::splat
