#include "s4d/scene/static_scene.h"

namespace s4d::scene {

StaticScene::StaticScene(engine::Context& ctx, const io::GaussianCloud& cloud, int sh_degree, const std::string& name,
                         splat::Storage sh_storage)
    : gaussians_(ctx, cloud, name, sh_storage), sh_degree_(sh_degree) {}

splat::GaussianParams StaticScene::at(double, const splat::Camera&) { return gaussians_.params(sh_degree_); }

std::string StaticScene::describe() const {
  return "static: " + std::to_string(gaussians_.size()) + " Gaussians (SH degree " +
         std::to_string(gaussians_.params(sh_degree_).sh_degree) + ")";
}

}  // namespace s4d::scene
