// Reads Gaussians that a scene source gave back from the device into a host cloud: what
// export-ply writes and where the viewer finds its orbit pivot.
#pragma once
#include "s4d/engine/context.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::scene {

// The cloud at g's active SH degree (the coefficients the renderer reads; stored higher ones are
// dropped), so a renderer of the file that uses every degree it stores draws what g draws. Waits.
// Throws std::invalid_argument when g replaces the SH colour with a colour buffer (a PLY has no
// place for it).
io::GaussianCloud download_cloud(engine::Context& ctx, const splat::GaussianParams& g);

}  // namespace s4d::scene
