// What the render protocols, the exact flow, the viewer and export-ply draw: a source of Gaussians
// for a given time and camera. A source is opened for one style (or the original scene), so "the
// Gaussians at time t for style S" is source_for_S.at(t, camera). Implementations: StaticScene (the
// static stage, the same Gaussians at every time) and DeformedScene (the 4DGS stage: canonical
// Gaussians moved by the deformation field to time t); the style MLPs (per-Gaussian colour and
// opacity from t and the Gaussian's depth in the camera) plug in behind the same call.
#pragma once
#include <cstdint>
#include <string>

#include "s4d/splat/rasterizer.h"

namespace s4d::scene {

class SceneSource {
 public:
  virtual ~SceneSource() = default;

  // The Gaussians at `time` in [0, 1] as seen by `camera` (view-dependent sources such as style MLPs
  // read it; geometry-only sources ignore it), in the rasterizer's layouts, with the SH degree the
  // run renders at. The buffers belong to the source and keep these values until the next call of
  // at(); sources that compute them wait for the device before returning.
  virtual splat::GaussianParams at(double time, const splat::Camera& camera) = 0;
  virtual uint32_t size() const = 0;  // Gaussians
  // False when every time gives the same Gaussians (playback runs; nothing moves).
  virtual bool dynamic() const = 0;
  // One line for logs and render.json, e.g. "static: 1234 Gaussians (SH degree 3)".
  virtual std::string describe() const = 0;
};

}  // namespace s4d::scene
