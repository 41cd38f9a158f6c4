#include "style_switch.h"

#include <algorithm>
#include <stdexcept>

namespace s4d::viewer {

namespace {

size_t index_of(const scene::TrainedRun& run, const std::string& style) {
  return static_cast<size_t>(std::find(run.styles.begin(), run.styles.end(), style) - run.styles.begin());
}

}  // namespace

StyleSwitch::StyleSwitch(engine::Context& ctx, const scene::TrainedRun& run, const scene::StyleChoice& start,
                         splat::Storage storage)
    : ctx_(&ctx), run_(&run), storage_(storage) {
  if (start.mix.empty()) {
    source_ = scene::open_scene(ctx, run, start.style, storage_);
  } else {
    std::unique_ptr<scene::BlendedScene> blend =
        scene::open_blend(ctx, run, start.style, start.mix, start.alpha, storage_);
    blended_ = blend.get();
    source_ = std::move(blend);
    shown_.mix = static_cast<int>(index_of(run, start.mix));
    shown_.alpha = start.alpha;
  }
  shown_.style = index_of(run, start.style);
}

std::string StyleSwitch::update(StyleSelection& want) {
  if (want.style == shown_.style && want.mix == shown_.mix) {
    if (blended_ != nullptr && want.alpha != shown_.alpha) {
      ctx_->wait_idle();  // the last frame may still read the blend's buffers
      blended_->set_alpha(want.alpha);
      shown_.alpha = want.alpha;
    }
    return "";
  }
  ctx_->wait_idle();  // the last frame may still read the old source's buffers
  const std::string& style = run_->styles[want.style];
  if (want.mix < 0) {
    source_ = scene::open_scene(*ctx_, *run_, style, storage_);
    blended_ = nullptr;
    shown_ = want;
    return "";
  }
  try {
    std::unique_ptr<scene::BlendedScene> blend =
        scene::open_blend(*ctx_, *run_, style, run_->styles[static_cast<size_t>(want.mix)], want.alpha, storage_);
    blended_ = blend.get();
    source_ = std::move(blend);
    shown_ = want;
    return "";
  } catch (const std::invalid_argument& e) {
    want.mix = shown_.mix;
    want.style = shown_.style;
    return e.what();
  }
}

}  // namespace s4d::viewer
