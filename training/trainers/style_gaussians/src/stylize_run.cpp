#include "s4d/style_gaussians/stylize_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>

#include "s4d/data/npy.h"
#include "s4d/data/poses_bounds.h"
#include "s4d/io/image_file.h"
#include "s4d/io/image_io.h"
#include "s4d/run/style_file.h"
#include "s4d/style_gaussians/style_trainer.h"
#include "s4d/frame_stylizers/registry.h"
#include "s4d/train/trainer.h"
#include "s4d/util/atomic_file.h"

namespace s4d::style_gaussians {

namespace fs = std::filesystem;

namespace {

// Identifies a style image by content, so a replaced file under the same name is noticed.
nlohmann::json image_key(const fs::path& path, const io::ImageF& image) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a over the 8-bit values
  for (float v : image.data) {
    h ^= static_cast<uint64_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    h *= 1099511628211ull;
  }
  return {{"path", fs::absolute(path).string()}, {"width", image.width}, {"height", image.height}, {"hash", std::to_string(h)}};
}

// The request without where its style image was read from: the same pixels from a moved or copied
// file continue the style rather than being refused as other settings.
nlohmann::json without_image_path(nlohmann::json request) {
  if (request.is_object() && request.contains("style_image") && request["style_image"].is_object())
    request["style_image"].erase("path");
  return request;
}

nlohmann::json read_json_or_null(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nullptr;
  }
}

// The stylized frames as a dataset on disk in the content's layout, for the scratch ablation's
// `style4d train`: DyNeRF gets poses_bounds.npy with hwf at the frames' resolution, D-NeRF its
// transforms files; points3D.ply is copied when there is one.
void write_dataset_layout(const data::Dataset& content, const fs::path& dir) {
  const fs::path& root = content.root;
  if (fs::exists(root / "points3D.ply")) fs::copy_file(root / "points3D.ply", dir / "points3D.ply", fs::copy_options::overwrite_existing);
  if (content.kind == "dynerf") {
    data::NpyArray poses = data::read_npy(root / "poses_bounds.npy");
    for (size_t c = 0; c < poses.shape[0]; ++c)
      for (size_t k : {data::kPosesBoundsHeight, data::kPosesBoundsWidth, data::kPosesBoundsFocal})
        poses.values[c * data::kPosesBoundsRow + k] /= content.downscale;
    data::write_npy(dir / "poses_bounds.npy", poses);
    return;
  }
  for (const char* split : {"transforms_train.json", "transforms_val.json", "transforms_test.json"})
    if (fs::exists(root / split)) fs::copy_file(root / split, dir / split, fs::copy_options::overwrite_existing);
}

}  // namespace

StylizeOutcome stylize_frames(engine::Context& ctx, const StylizeRequest& req) {
  const auto start = std::chrono::steady_clock::now();
  validate(req.config);
  // The run is held shared while its style trains: `train --resume` (exclusive) cannot change the
  // geometry under it, and other styles of the run may train at once (run_lock.h). A folder that is
  // not a run gets read_trained_run's message.
  StylizeOutcome out;
  if (fs::exists(req.run / "run.json")) out.run_lock.emplace(req.run, run::RunLock::Mode::shared);
  out.run = scene::read_trained_run(req.run);
  const scene::TrainedRun& run = out.run;
  out.name = req.name.empty() ? req.style_image.stem().string() : req.name;
  const std::string& name = out.name;
  if (name.empty() || name == "original" || name.find('/') != std::string::npos)
    throw std::invalid_argument("--style '" + name + "': a style needs a plain name other than 'original'");
  out.style_image = io::read_image_rgb(req.style_image);
  const io::ImageF& style_image = out.style_image;
  out.stylizer = frame_stylizers::make_stylizer(req.config.stylizer,
                                        {.weights = req.weights, .style_size = req.style_size, .context = &ctx});
  const frame_stylizers::Stylizer* stylizer = out.stylizer.get();
  out.dir = run::style_dir(run.root, name);
  fs::create_directories(out.dir);
  out.style_lock.emplace(out.dir);  // one writer per style

  const nlohmann::json network = req.weights.empty() ? nlohmann::json(nullptr)
                                                     : nlohmann::json{{"weights", fs::absolute(req.weights).string()},
                                                                      {"style_size", req.style_size}};
  nlohmann::json request = {{"style_image", image_key(req.style_image, style_image)},
                            {"network", network},
                            {"settings", to_json(req.config)}};
  if (req.scratch_iterations > 0) request["scratch_iterations"] = req.scratch_iterations;
  if (req.time_budget > 0) request["time_budget"] = req.time_budget;
  const nlohmann::json previous = read_json_or_null(out.dir / "request.json");
  if (req.restart)
    for (const char* stale : {"checkpoint.s4dckpt", "style.s4dstyle", "run", "eval", "spiral", "stylize.json"})
      fs::remove_all(out.dir / stale);
  else if (!previous.is_null() && without_image_path(previous) != without_image_path(request))
    throw std::invalid_argument("style " + name + " of " + run.root.string() + " was started with other settings (" +
                                out.dir.string() + "/request.json); pass --restart to train it again, or another --style NAME");
  fs::create_directories(out.dir);
  util::write_file_atomic(out.dir / "request.json", request.dump(2) + "\n");
  // The style image travels with the style (bench's style metrics read it), 8-bit as its key hashes it.
  io::write_png(run::style_image_path(run.root, name), style_image);

  out.style_image_key = request.at("style_image");

  // Stage 3.
  out.settings = {.strength = req.config.strength, .seed = req.config.seed};
  const nlohmann::json key = {{"stylizer", stylizer->name()}, {"strength", req.config.strength}, {"seed", req.config.seed},
                              {"style_image", without_image_path(request).at("style_image")}, {"network", network}};
  out.frames = stylize_dataset(run.dataset, *stylizer, style_image, out.settings, key, out.dir / "stylized");
  out.stage3_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

void train_style(engine::Context& ctx, const StylizeRequest& req, StylizeOutcome& out, const std::atomic<bool>& stop,
                 double deadline) {
  const scene::TrainedRun& run = out.run;
  const std::string& name = out.name;
  nlohmann::json& stage4 = out.stage4;
  fs::path& eval_dir = out.eval_dir;
  eval_dir = out.dir / "eval";
  if (req.config.method == run::StyleMethod::scratch) {
    write_dataset_layout(run.dataset, out.dir / "stylized");
    const fs::path scratch = out.dir / "run";
    run::TrainConfig config = run.config;
    if (req.scratch_iterations > 0) run::set_iterations(config, req.scratch_iterations);
    config.time_budget = deadline;
    std::unique_ptr<train::Trainer> trainer = fs::exists(scratch / "run.json")
                                                  ? train::Trainer::resume(ctx, scratch)
                                                  : std::make_unique<train::Trainer>(ctx, out.dir / "stylized", config, scratch);
    const train::TrainResult r = trainer->run(stop);
    if (!r.complete) return;
    run::StyleFile file;
    file.method = run::StyleMethod::scratch;
    file.settings = to_json(req.config);
    file.count = r.num_gaussians;
    run::write_style_file(run::style_file_path(run.root, name), file);
    stage4 = {{"seconds", r.seconds}, {"test_psnr_vs_stylized", r.test.psnr}, {"test_ssim_vs_stylized", r.test.ssim}};
    eval_dir = scratch / "eval";
  } else {
    StyleTrainer trainer(ctx, run, out.frames.dataset, name, req.config, deadline);
    const StyleResult r = trainer.run(stop);
    if (!r.complete) return;
    stage4 = {{"seconds", r.seconds}, {"iterations", r.iteration}, {"test_psnr_vs_stylized", r.test.psnr},
              {"test_ssim_vs_stylized", r.test.ssim}, {"stylized_gaussians", r.stylized_gaussians}};
    if (!r.time_budget.is_null()) stage4["time_budget"] = r.time_budget;
  }

  out.complete = true;
}

}  // namespace s4d::style_gaussians
