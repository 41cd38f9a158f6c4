// The files of a run directory (ARCHITECTURE.md "Files on disk"):
//   RUN/run.json                  what was trained from what: data path, stage, settings (for --resume)
//   RUN/checkpoint/state.s4dckpt  everything needed to continue (checkpoint.h)
//   RUN/geometry/gaussians.ply    the Gaussians in the standard 3DGS PLY layout
//   RUN/train.json                results: test_psnr, test_ssim, seconds, num_gaussians, settings, per view
//   RUN/eval/*.png                test-view renders of the last evaluation
//   RUN/loss.csv                  iteration, loss, l1, ssim, gaussians, seconds (one row per logged step)
#pragma once
#include <filesystem>

namespace s4d::train {

struct RunDir {
  std::filesystem::path root;
  std::filesystem::path run_json() const { return root / "run.json"; }
  std::filesystem::path checkpoint() const { return root / "checkpoint" / "state.s4dckpt"; }
  std::filesystem::path gaussians_ply() const { return root / "geometry" / "gaussians.ply"; }
  std::filesystem::path train_json() const { return root / "train.json"; }
  std::filesystem::path eval_dir() const { return root / "eval"; }
  std::filesystem::path loss_csv() const { return root / "loss.csv"; }
};

}  // namespace s4d::train
