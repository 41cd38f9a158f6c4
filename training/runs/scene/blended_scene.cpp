#include "s4d/scene/blended_scene.h"

#include <sstream>

#include "s4d/scene/style_blend.h"

namespace s4d::scene {

BlendedScene::BlendedScene(engine::Context& ctx, std::unique_ptr<SceneSource> base, run::StyleFile a,
                           const std::string& name_a, run::StyleFile b, const std::string& name_b, float alpha,
                           splat::Storage storage)
    : a_(std::move(a)), b_(std::move(b)), alpha_(alpha) {
  styled_ = std::make_unique<StyledScene>(ctx, std::move(base), blend_styles(a_, b_, alpha), name_a + " + " + name_b,
                                          storage);
}

void BlendedScene::set_alpha(float alpha) {
  styled_->restyle(blend_styles(a_, b_, alpha));
  alpha_ = alpha;
}

std::string BlendedScene::describe() const {
  std::ostringstream s;
  s << styled_->describe() << ", blend factor " << alpha_;
  return s.str();
}

}  // namespace s4d::scene
