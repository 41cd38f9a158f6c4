#include "s4d/viewer/capture.h"

#include <stdexcept>

#include "s4d/engine/recorder.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/viewer/dataset_cameras.h"
#include "s4d/viewer/frame_renderer.h"

namespace s4d::viewer {

void capture(engine::Context& ctx, const scene::TrainedRun& run, const CaptureRequest& request) {
  const std::vector<io::CameraView> cameras = dataset_cameras(run.dataset);
  if (request.camera >= cameras.size())
    throw std::invalid_argument("--camera " + std::to_string(request.camera) + ": the run's dataset has cameras 0.." +
                                std::to_string(cameras.size() - 1));
  if (!(request.time >= 0 && request.time <= 1))
    throw std::invalid_argument("--time " + std::to_string(request.time) + ": expected a time in [0, 1]");
  const std::unique_ptr<scene::SceneSource> source = scene::open_scene(ctx, run, request.style, request.storage);
  FrameRenderer renderer(ctx, run.dataset.background);
  renderer.render_now(*source, splat::to_splat_camera(cameras[request.camera]), request.time, PixelOrder::rgba);
  io::write_png(request.png, renderer.read_rgb());
}

}  // namespace s4d::viewer
