#include "s4d/viewer/scene_source.h"

#include <stdexcept>

namespace s4d::viewer {

StaticSceneSource::StaticSceneSource(engine::Context& ctx, const io::GaussianCloud& cloud)
    : gaussians_(ctx, cloud, "viewer gaussians") {}

splat::GaussianParams StaticSceneSource::params_at(double /*time: static scene*/, size_t style) {
  if (style >= styles_.size())
    throw std::out_of_range("style index " + std::to_string(style) + " past the " + std::to_string(styles_.size()) +
                            " styles of this scene");
  return gaussians_.params();
}

std::unique_ptr<SceneSource> make_scene_source(engine::Context& ctx, const RunScene& scene) {
  if (scene.stage != "static")
    throw std::runtime_error(scene.root.string() + ": stage '" + scene.stage +
                             "' is not readable by this viewer yet (it shows the static stage)");
  return std::make_unique<StaticSceneSource>(ctx, scene.cloud);
}

size_t find_style(const SceneSource& source, const std::string& name) {
  const std::vector<std::string>& styles = source.styles();
  std::string known;
  for (size_t i = 0; i < styles.size(); ++i) {
    if (styles[i] == name) return i;
    known += (i ? ", " : "") + styles[i];
  }
  throw std::invalid_argument("--style " + name + ": this run has no such style; it has: " + known +
                              " (trained styles come from the stylization stage)");
}

}  // namespace s4d::viewer
