#include "s4d/viewer/capture.h"

#include <stdexcept>

#include "s4d/engine/recorder.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/viewer/frame_renderer.h"
#include "s4d/viewer/scene_source.h"

namespace s4d::viewer {

void capture(engine::Context& ctx, const RunScene& scene, const CaptureRequest& request) {
  if (request.camera >= scene.cameras.size())
    throw std::invalid_argument("--camera " + std::to_string(request.camera) + ": the run's dataset has cameras 0.." +
                                std::to_string(scene.cameras.size() - 1));
  if (!(request.time >= 0 && request.time <= 1))
    throw std::invalid_argument("--time " + std::to_string(request.time) + ": expected a time in [0, 1]");
  const std::unique_ptr<SceneSource> source = make_scene_source(ctx, scene);
  const size_t style = find_style(*source, request.style);
  FrameRenderer renderer(ctx, *source, scene.background);
  engine::Recorder rec(ctx, "viewer capture");
  renderer.render(splat::to_splat_camera(scene.cameras[request.camera]), request.time, style, PixelOrder::rgba, rec);
  ctx.run(std::move(rec));
  io::write_png(request.png, renderer.read_rgb());
}

}  // namespace s4d::viewer
