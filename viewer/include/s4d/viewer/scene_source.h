// Where the viewer's Gaussians come from: device parameters at a time and in a style. The static
// stage's run gives the same Gaussians at every time and only the original style; the 4D source
// (deformation field at time t) and the style heads plug in behind the same interface.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/viewer/run_scene.h"

namespace s4d::viewer {

class SceneSource {
 public:
  virtual ~SceneSource() = default;
  // Style names; index 0 is always "original" (the unstylised scene).
  virtual const std::vector<std::string>& styles() const = 0;
  // Device parameters at `time` in [0, 1] in style `style` (an index into styles()). They stay
  // valid until the next call. Throws std::out_of_range for a style index past styles().
  virtual splat::GaussianParams params_at(double time, size_t style) = 0;
  virtual uint32_t gaussian_count() const = 0;
  // False when every time gives the same Gaussians (the playback still runs; nothing moves).
  virtual bool dynamic() const = 0;
};

// The static stage: one Gaussian cloud on the device, the same at every time, style "original".
class StaticSceneSource final : public SceneSource {
 public:
  StaticSceneSource(engine::Context& ctx, const io::GaussianCloud& cloud);
  const std::vector<std::string>& styles() const override { return styles_; }
  splat::GaussianParams params_at(double time, size_t style) override;
  uint32_t gaussian_count() const override { return gaussians_.size(); }
  bool dynamic() const override { return false; }

 private:
  splat::DeviceGaussians gaussians_;
  std::vector<std::string> styles_{"original"};
};

// The source for a run: its stage decides which (today every run is the static stage).
std::unique_ptr<SceneSource> make_scene_source(engine::Context& ctx, const RunScene& scene);

// The index of style `name` in source.styles(); std::invalid_argument listing the available
// styles when there is none of that name.
size_t find_style(const SceneSource& source, const std::string& name);

}  // namespace s4d::viewer
