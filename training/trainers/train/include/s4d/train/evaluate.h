// Test-view evaluation as 3DGS reports it: each render clamped to [0, 1], PSNR from the mean squared
// error over all pixels and channels (s4d/io/psnr.h), SSIM with the 11x11 Gaussian window (sigma 1.5) averaged over
// the map (the training loss's own kernels), both averaged over the views.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "s4d/io/moving_content.h"

#include "s4d/data/dataset.h"
#include "s4d/data/frame_cache.h"
#include "s4d/engine/buffer.h"
#include "s4d/optim/image_loss.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/train/view_target.h"

namespace s4d::train {

struct ViewScore {
  std::string name;
  double time = 0, psnr = 0, ssim = 0;
};

struct Evaluation {
  double psnr = 0, ssim = 0;  // means over the views
  std::vector<ViewScore> views;
  // Over the pixels that move, per camera seen at three or more times (io/moving_content.h).
  io::MovingScore moving;
  double background_psnr = 0;  // mean PSNR of an empty render (the background alone) against the same views
};

// The periodic tests during a stage use this many test views; the closing test uses all.
constexpr size_t kPeriodicTestViews = 8;
// An evenly spaced subset of at most k views, always including the first.
std::vector<const data::View*> spread_views(const std::vector<const data::View*>& views, size_t k);

class Evaluator {
 public:
  explicit Evaluator(engine::Context& ctx);
  // The Gaussians to render a view with (a dynamic model deforms them to the view's time first).
  using ParamsAt = std::function<splat::GaussianParams(const data::View&)>;

  // Renders every view; when `save_dir` is set, writes each render there as
  // <view name with '/' as '_'>.png.
  Evaluation evaluate(splat::Rasterizer& rast, const ParamsAt& params_at, const std::vector<const data::View*>& views,
                      data::FrameCache& frames, const std::array<float, 3>& background,
                      const std::filesystem::path& save_dir = {});

 private:
  engine::Context* ctx_;
  optim::ImageLoss loss_;
  engine::Buffer image_;
  ViewTarget target_;  // the view's frame, and the SSIM's image gradient (unused)
};

}  // namespace s4d::train
