// The files of a run directory (ARCHITECTURE.md "Files on disk"):
//   RUN/run.json                  what was trained from what: data path, stage, settings (run_json.h)
//   RUN/checkpoint/state.s4dckpt  everything needed to continue (checkpoint.h)
//   RUN/checkpoint/state.prev.s4dckpt  the one before it, which --resume falls back to when the
//                                 newest is damaged (write_checkpoint_rotating)
//   RUN/geometry/gaussians.ply    the Gaussians in the standard 3DGS PLY layout
//   RUN/train.json                results: test_psnr, test_ssim, seconds, num_gaussians, settings, per view
//   RUN/eval/*.png                test-view renders of the last evaluation
//   RUN/loss.csv                  iteration, loss, l1, ssim, gaussians, seconds (one row per logged step)
//   RUN/.lock                     held (flock) by the style4d process writing the run (run_lock.h)
#pragma once
#include <algorithm>
#include <filesystem>

namespace s4d::run {

struct RunDir {
  std::filesystem::path root;
  std::filesystem::path run_json() const { return root / "run.json"; }
  std::filesystem::path checkpoint() const { return root / "checkpoint" / "state.s4dckpt"; }
  std::filesystem::path previous_checkpoint() const { return root / "checkpoint" / "state.prev.s4dckpt"; }
  std::filesystem::path gaussians_ply() const { return root / "geometry" / "gaussians.ply"; }
  std::filesystem::path train_json() const { return root / "train.json"; }
  std::filesystem::path eval_dir() const { return root / "eval"; }
  std::filesystem::path loss_csv() const { return root / "loss.csv"; }
  std::filesystem::path style_dir() const { return root / "style"; }

  // Whether `path` is one of the run's own files (run.json, train.json, loss.csv, .lock) or lies in
  // one of its folders (checkpoint/, geometry/, eval/, style/): what other commands write must go
  // elsewhere (RUN/viewer/ and any new name beside the run's files are fine). Symlinks are resolved.
  bool owns(const std::filesystem::path& path) const {
    namespace fs = std::filesystem;
    const fs::path p = fs::weakly_canonical(fs::absolute(path)), r = fs::weakly_canonical(fs::absolute(root));
    for (const fs::path& file : {run_json(), train_json(), loss_csv(), root / ".lock"})
      if (p == fs::weakly_canonical(fs::absolute(file))) return true;
    for (const fs::path& dir : {root / "checkpoint", root / "geometry", eval_dir(), style_dir()}) {
      const fs::path d = fs::weakly_canonical(fs::absolute(dir));
      const auto [end, ignored] = std::mismatch(d.begin(), d.end(), p.begin(), p.end());
      if (end == d.end()) return true;
    }
    return r == p;
  }
};

}  // namespace s4d::run
