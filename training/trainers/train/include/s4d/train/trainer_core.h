// What every trainer (the scene's stages 1 and 2, the style's stage 4) holds and does alike: its
// training and test views and their frames, the view sampler, the view's frame target, the
// rasterizer, the image loss, Adam, the evaluator and the guard's state (recovery, the last state
// known finite, the seconds of earlier runs); one forward-and-loss recording and one evaluation.
// A trainer derives from it and adds its own model, step and checkpoint.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/data/frame_cache.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/model/checkpoint.h"
#include "s4d/optim/adam.h"
#include "s4d/optim/image_loss.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/train/divergence.h"
#include "s4d/train/evaluate.h"
#include "s4d/train/stage_runner.h"
#include "s4d/train/view_sampler.h"
#include "s4d/train/view_target.h"

namespace s4d::train {

struct TrainerParts {
  std::string name;  // "training", "style": names the device buffers ("NAME rasterizer", "NAME target", ...)
  const data::Dataset* frames_of = nullptr;  // the frames the views come from
  std::vector<const data::View*> train_views, test_views;  // no test view: kPeriodicTestViews of the training ones
  size_t frame_cache_bytes = 0;
  uint32_t adam_groups = 0;
  uint32_t seed = 0;  // the view sampler's, over all training views
  std::array<float, 3> background{};
  Recovery recovery;  // what the guard starts from (the settings' learning-rate scale)
};

class TrainerCore {
 public:
  TrainerCore(engine::Context& ctx, TrainerParts parts);
  TrainerCore(const TrainerCore&) = delete;
  TrainerCore& operator=(const TrainerCore&) = delete;

  // Records what `params` returns (the Gaussians of the view in hand, recorded into the same
  // submission), rasterizes them with `cam` against the frame `target` holds, and records the
  // image loss, which writes d loss / d pixel to target.image_gradient(). An overflow of the
  // rasterizer's instance buffers grows them and records it again. Returns the loss.
  using RecordParams = std::function<splat::GaussianParams(engine::Recorder&)>;
  optim::LossValue forward_loss(const splat::Camera& cam, float ssim_weight, const RecordParams& params);

  // The scores of `views` rendered from what `params_at` gives for each; `save_dir`: their renders.
  Evaluation evaluate(const Evaluator::ParamsAt& params_at, const std::vector<const data::View*>& views,
                      const std::filesystem::path& save_dir = {});

  // The guard's save: a state whose `divergence` was found is refused (StateOutOfRange, nothing
  // written); otherwise `write` writes it, and it becomes the last good state.
  void save_checked(model::Checkpoint cp, Divergence divergence, const std::function<void(const model::Checkpoint&)>& write);

  engine::Context& ctx;
  std::string forward_label;  // "NAME forward and loss": the submission's name in timings and errors
  std::vector<const data::View*> train_views, test_views;
  data::FrameCache frames;
  splat::Rasterizer rast;
  optim::ImageLoss loss;
  optim::Adam adam;
  Evaluator evaluator;
  ViewSampler sampler;
  ViewTarget target;  // the view in hand's frame and its image gradient
  std::array<float, 3> background;
  Recovery recovery;
  model::Checkpoint last_good;  // the last state known finite: what a non-finite step rolls back to
  double seconds_before = 0;    // training seconds of the runs before this one (from the checkpoint)
};

// The array `name` among a checkpoint's extra arrays; std::runtime_error naming `where` and the
// array when it is missing.
const std::vector<float>& checkpoint_array(const model::Checkpoint& cp, const std::string& name, const std::string& where);

}  // namespace s4d::train
