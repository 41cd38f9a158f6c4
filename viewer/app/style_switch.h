// Keeps the viewer's scene source in step with the style the panel and keys pick: one of the run's
// styles, or the blend of two with a factor (training/runs/scene/style_blend.h). A new style or second
// style reopens the source; a new blend factor only re-blends the open one's arrays on the host and
// uploads them, so dragging the slider reads no file.
#pragma once
#include <memory>
#include <string>

#include "s4d/engine/context.h"
#include "s4d/scene/trained_run.h"

namespace s4d::viewer {

struct StyleSelection {
  size_t style = 0;   // index into run.styles
  int mix = -1;       // index into run.styles of the style blended in, or -1: none
  float alpha = 0.5f; // weight of the mix style, in [0, 1]
};

class StyleSwitch {
 public:
  // Opens `start`, and every later style, with `storage` (scene::open_scene); its errors (an unknown
  // style, styles that cannot be blended) propagate.
  StyleSwitch(engine::Context& ctx, const scene::TrainedRun& run, const scene::StyleChoice& start,
              splat::Storage storage = splat::Storage::f32);

  // What `start` was, as panel indices.
  const StyleSelection& shown() const { return shown_; }
  scene::SceneSource& source() { return *source_; }

  // Makes the source show `want`, waiting for the device first if anything changes. Styles that
  // cannot be blended (a "scratch" style) leave the source as it was, set want.mix back to what is
  // shown and return why; otherwise returns "".
  std::string update(StyleSelection& want);

 private:
  engine::Context* ctx_;
  const scene::TrainedRun* run_;
  splat::Storage storage_;
  std::unique_ptr<scene::SceneSource> source_;
  scene::BlendedScene* blended_ = nullptr;  // source_ when it is a blend
  StyleSelection shown_;
};

}  // namespace s4d::viewer
