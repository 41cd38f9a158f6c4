// What the render protocols, the exact flow, the viewer and export-ply draw: a source of Gaussians
// for a given time and camera. A source is opened for one style (or the original scene), so "the
// Gaussians at time t for style S" is source_for_S.at(t, camera). Implementations: StaticScene (the
// static stage, the same Gaussians at every time) and DeformedScene (the 4DGS stage: canonical
// Gaussians moved by the deformation field to time t); the style MLPs (per-Gaussian colour and
// opacity from t and the Gaussian's depth in the camera) plug in behind the same call.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::scene {

class SceneSource {
 public:
  virtual ~SceneSource() = default;

  // The Gaussians at `time` in [0, 1] as seen by `camera` (view-dependent sources such as style MLPs
  // read it; geometry-only sources ignore it), in the rasterizer's layouts, with the SH degree the
  // run renders at. Sources that compute them record that work into the caller's `rec`: the
  // buffers hold these values once `rec` has run (after a barrier() in `rec` for work recorded
  // behind it), and keep them until the next call. `rec` must be submitted before the next call
  // (a source may skip work whose result its buffers already hold).
  virtual splat::GaussianParams record(engine::Recorder& rec, double time, const splat::Camera& camera) = 0;
  // record() into a command buffer of its own, submitted and waited for (no submission where
  // there is nothing to compute).
  virtual splat::GaussianParams at(double time, const splat::Camera& camera) = 0;
  virtual uint32_t size() const = 0;  // Gaussians
  // False when every time gives the same Gaussians (playback runs; nothing moves).
  virtual bool dynamic() const = 0;
  // One line for logs and render.json, e.g. "static: 1234 Gaussians (SH degree 3)".
  virtual std::string describe() const = 0;
  // Bytes of device memory this source holds in SH (canonical, deformed, a style's deltas and
  // styled SH) and style MLP weights: what half storage (splat::Storage::f16) shrinks.
  virtual size_t sh_style_bytes() const = 0;

 protected:
  // at() for a source that computes: record() in one submission, waited for.
  splat::GaussianParams record_and_run(engine::Context& ctx, double time, const splat::Camera& camera) {
    engine::Recorder rec(ctx, "scene at time");
    const splat::GaussianParams g = record(rec, time, camera);
    ctx.run(std::move(rec));
    return g;
  }
};

}  // namespace s4d::scene
