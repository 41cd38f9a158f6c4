// Whether a capture shows anything move, from its frames alone, before any training: on a rig, each
// camera's frames at a few times against its first. A scene that does not move gets no deformation
// field (the 4DGS stage is skipped: its parameters would model nothing). A monocular capture's frames
// differ by viewpoint as well as by motion, so the frames cannot tell, and the field stays.
#pragma once
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "s4d/data/dataset.h"
#include "s4d/data/frame_cache.h"
#include "s4d/run/train_config.h"

namespace s4d::train {

// A pixel changed when a channel differs by more than this (8-bit steps and sensor noise stay
// below; the built-in scene's sliding box changes every pixel it crosses by more than 0.2).
inline constexpr float kPixelChange = 0.05f;
// A camera sees motion when more than this share of its pixels changed at a sampled time.
inline constexpr double kMovingShare = 0.002;
// Times sampled per camera, spread over its frames (the first is the reference).
inline constexpr uint32_t kMotionSamples = 5;

enum class Motion { still, moving, unknown };

struct MotionCheck {
  Motion motion = Motion::unknown;
  double changed_share = 0;  // the largest share of changed pixels over the cameras and times compared
  uint32_t cameras = 0, comparisons = 0;
  std::string why;  // one line, train.json's recipe
  nlohmann::json to_json() const;
};

MotionCheck check_motion(const data::Dataset& dataset, data::FrameCache& frames);

// A new run's decision: when the frames show no motion and the fine stage's length was not asked for
// (TrainConfig::fine_iterations_given), the 4DGS stage is skipped and its steps go to the static
// stage, said in one line. Returns train.json's recipe "deformation_field": the check and "trained".
nlohmann::json skip_field_if_still(run::TrainConfig& config, const data::Dataset& dataset, data::FrameCache& frames);

}  // namespace s4d::train
