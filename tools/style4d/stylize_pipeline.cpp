#include "stylize_pipeline.h"

#include <limits>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

#include "s4d/bench/contact_sheet.h"
#include "s4d/data/frame_cache.h"
#include "s4d/data/npy.h"
#include "s4d/metrics/flow.h"
#include "s4d/metrics/warp_loss.h"
#include "s4d/protocols/protocol.h"
#include "s4d/protocols/protocol_render.h"
#include "s4d/run/run_lock.h"
#include "s4d/run/style_file.h"
#include "s4d/scene/trained_run.h"
#include "s4d/style/style_trainer.h"
#include "s4d/style/stylized_frames.h"
#include "s4d/io/image_file.h"
#include "s4d/stylize/registry.h"
#include "s4d/stylize/warp_error.h"
#include "s4d/train/trainer.h"
#include "s4d/util/atomic_file.h"

namespace s4d::cli {

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
      for (size_t k : {4, 9, 14}) poses.values[c * 17 + k] /= content.downscale;  // H, W, focal
    data::write_npy(dir / "poses_bounds.npy", poses);
    return;
  }
  for (const char* split : {"transforms_train.json", "transforms_val.json", "transforms_test.json"})
    if (fs::exists(root / split)) fs::copy_file(root / split, dir / split, fs::copy_options::overwrite_existing);
}

size_t frames_per_camera(const data::Dataset& d) {
  std::map<int, size_t> counts;
  for (const data::View& v : d.views) ++counts[v.camera_index];
  size_t most = 0;
  for (const auto& [camera, n] : counts) most = std::max(most, n);
  return most;
}

std::vector<io::ImageF> read_sequence(const fs::path& dir, const protocols::SequenceRecord& seq) {
  std::vector<io::ImageF> out;
  for (const std::string& f : seq.files) out.push_back(io::read_png(dir / seq.dir / f));
  return out;
}

// Mean over consecutive pairs of the warp loss (metrics/warp_loss.h) under the renderer's exact flow
// of the original scene, read from FLOW_DIR/fw_NNNN.exr and bw_NNNN.exr. Pairs occluded everywhere
// are left out, as Style4D-Bench does; NaN (null in stylize.json) when every pair is.
double exact_flow_warp_error(const std::vector<io::ImageF>& frames, const fs::path& flow_dir) {
  auto flow = [&](const char* prefix, size_t pair) {
    return metrics::read_flow_exr(flow_dir / protocols::flow_file_name(prefix, static_cast<int>(pair)));
  };
  double sum = 0;
  size_t scored = 0;
  for (size_t k = 0; k + 1 < frames.size(); ++k) {
    const metrics::PairWarpError pair = metrics::warp_error(frames[k], frames[k + 1], flow("fw", k), flow("bw", k));
    if (!pair.scored()) continue;
    sum += pair.error;
    ++scored;
  }
  return scored > 0 ? sum / static_cast<double>(scored) : std::numeric_limits<double>::quiet_NaN();
}

// Renders the spiral path from the run's original scene and from the style, and measures the
// temporal warp error of each. The 2D baseline on the same path: the stage-3 stylizer run on the
// original spiral render as a video, which is what restyling the spiral's frames in 2D gives (frames
// in DIR/spiral/stylized_2d). Two motions: DIS flow of the original render (occlusions left out), the
// one stage 3's temporal warm start also follows, and the renderer's exact flow (Style4D-Bench's
// warp loss), which no 2D stylizer sees; the style keeps the geometry, so one flow serves all three.
nlohmann::json spiral_consistency(engine::Context& ctx, const scene::TrainedRun& run, const std::string& name,
                                  const fs::path& dir, int frames, const stylize::Stylizer& stylizer,
                                  const io::ImageF& style_image, const stylize::StylizeSettings& settings) {
  const std::vector<protocols::Sequence> seqs =
      protocols::build_protocol(run.dataset, protocols::parse_path("spiral"), frames);
  std::vector<std::vector<io::ImageF>> rendered;
  for (const std::string& source : {std::string("original"), name}) {
    const fs::path out = dir / "spiral" / (source == "original" ? "original" : "styled");
    fs::remove_all(out);
    const std::unique_ptr<scene::SceneSource> scene = scene::open_scene(ctx, run, source);
    protocols::RenderOptions options;
    options.background = run.dataset.background;
    options.flow = source == "original";
    const protocols::ProtocolResult r =
        protocols::render_protocol(ctx, *scene, protocols::parse_path("spiral"), seqs, out, options);
    rendered.push_back(read_sequence(out, r.record.sequences.front()));
  }
  std::cerr << "[consistency] the 2D stylizer on the " << rendered[0].size() << " spiral frames\n";
  const std::vector<io::ImageF> stylized_2d = stylizer.stylize(rendered[0], style_image, settings);
  const fs::path out_2d = dir / "spiral" / "stylized_2d";
  fs::remove_all(out_2d);
  fs::create_directories(out_2d);
  for (size_t i = 0; i < stylized_2d.size(); ++i) {
    char file[32];
    std::snprintf(file, sizeof file, "%04zu.png", i);
    io::write_png(out_2d / file, stylized_2d[i]);
  }
  const fs::path flow = dir / "spiral" / "original" / "flow";
  return {{"frames", frames},
          {"original_render", stylize::warp_error(rendered[0], rendered[0])},
          {"styled_render", stylize::warp_error(rendered[0], rendered[1])},
          {"stylized_2d", stylize::warp_error(rendered[0], stylized_2d)},
          {"exact_flow",
           {{"original_render", exact_flow_warp_error(rendered[0], flow)},
            {"styled_render", exact_flow_warp_error(rendered[1], flow)},
            {"stylized_2d", exact_flow_warp_error(stylized_2d, flow)}}}};
}

// The test camera's views in time order (DyNeRF: cam00 over its frames); empty when the test views
// do not share one camera (D-NeRF), where a warp error over them would mix viewpoints.
std::vector<const data::View*> test_sequence(const data::Dataset& d) {
  std::vector<const data::View*> test;
  for (const data::View& v : d.views)
    if (v.test) test.push_back(&v);
  std::sort(test.begin(), test.end(), [](const data::View* a, const data::View* b) { return a->time < b->time; });
  const bool one_camera = std::all_of(test.begin(), test.end(), [&](const data::View* v) {
    return v->camera_index >= 0 && v->camera_index == test.front()->camera_index;
  });
  return one_camera ? test : std::vector<const data::View*>{};
}

// Like for like on the test camera: the temporal warp error of the stage-3 frames and of the
// renders in the style over the same fixed camera and times (the spiral moves the camera, so its
// error is not comparable with fixed-camera sequences). Null without a fixed test camera.
nlohmann::json test_camera_consistency(const scene::TrainedRun& run, const data::Dataset& stylized, const fs::path& eval_dir) {
  const std::vector<const data::View*> seq = test_sequence(run.dataset);
  if (seq.size() < 2) return nullptr;
  data::FrameCache content_frames(run.dataset, size_t{256} << 20);
  std::vector<io::ImageF> content, frames_2d, rendered;
  for (const data::View* v : seq) {
    std::string flat = v->name;
    std::replace(flat.begin(), flat.end(), '/', '_');
    content.push_back(content_frames.get(*v));
    frames_2d.push_back(io::read_png(stylized.views[static_cast<size_t>(v - run.dataset.views.data())].image));
    rendered.push_back(io::read_png(eval_dir / (flat + ".png")));
  }
  return {{"frames", seq.size()},
          {"content", stylize::warp_error(content, content)},
          {"stylized_frames_2d", stylize::warp_error(content, frames_2d)},
          {"styled_render", stylize::warp_error(content, rendered)}};
}

// Rows: content frames, stage-3 frames, renders in the style; columns: test-camera frames over time.
void write_contact_sheet(const scene::TrainedRun& run, const data::Dataset& stylized, const fs::path& eval_dir,
                         const fs::path& file) {
  std::vector<const data::View*> test;
  for (const data::View& v : run.dataset.views)
    if (v.test) test.push_back(&v);
  if (test.empty()) return;
  std::sort(test.begin(), test.end(), [](const data::View* a, const data::View* b) { return a->time < b->time; });
  data::FrameCache content(run.dataset, size_t{64} << 20);
  bench::SheetRow rows[3] = {{"content", {}}, {"stage 3 (2D stylizer)", {}}, {"Style4D render", {}}};
  std::vector<int> index;
  const size_t samples = std::min<size_t>(4, test.size());
  for (size_t k = 0; k < samples; ++k) {
    const size_t i = samples == 1 ? 0 : k * (test.size() - 1) / (samples - 1);
    const data::View& v = *test[i];
    std::string flat = v.name;
    std::replace(flat.begin(), flat.end(), '/', '_');
    rows[0].frames.push_back(content.get(v));
    rows[1].frames.push_back(io::read_png(stylized.views[static_cast<size_t>(&v - run.dataset.views.data())].image));
    rows[2].frames.push_back(io::read_png(eval_dir / (flat + ".png")));
    index.push_back(static_cast<int>(i));
  }
  io::write_png(file, bench::contact_sheet({rows[0], rows[1], rows[2]}, index));
}

}  // namespace

StylizeOutcome stylize_run(engine::Context& ctx, const StylizeRequest& req, const std::atomic<bool>& stop) {
  const auto start = std::chrono::steady_clock::now();
  style::validate(req.config);
  // The run is held shared while its style trains: `train --resume` (exclusive) cannot change the
  // geometry under it, and other styles of the run may train at once (run_lock.h). A folder that is
  // not a run gets read_trained_run's message.
  std::optional<run::RunLock> run_lock;
  if (fs::exists(req.run / "run.json")) run_lock.emplace(req.run, run::RunLock::Mode::shared);
  const scene::TrainedRun run = scene::read_trained_run(req.run);
  const std::string name = req.name.empty() ? req.style_image.stem().string() : req.name;
  if (name.empty() || name == "original" || name.find('/') != std::string::npos)
    throw std::invalid_argument("--name '" + name + "': a style needs a plain name other than 'original'");
  const io::ImageF style_image = io::read_image_rgb(req.style_image);
  const std::unique_ptr<stylize::Stylizer> stylizer = stylize::make_stylizer(
      req.config.stylizer, {.weights = req.weights, .style_size = req.style_size, .context = &ctx});
  StylizeOutcome out;
  out.dir = run::style_dir(run.root, name);
  fs::create_directories(out.dir);
  const run::RunLock style_lock(out.dir);  // one writer per style

  const nlohmann::json network = req.weights.empty() ? nlohmann::json(nullptr)
                                                     : nlohmann::json{{"weights", fs::absolute(req.weights).string()},
                                                                      {"style_size", req.style_size}};
  const nlohmann::json request = {{"style_image", image_key(req.style_image, style_image)},
                                  {"network", network},
                                  {"settings", style::to_json(req.config)}};
  const nlohmann::json previous = read_json_or_null(out.dir / "request.json");
  if (req.restart)
    for (const char* stale : {"checkpoint.s4dckpt", "style.s4dstyle", "run", "eval", "spiral", "stylize.json"})
      fs::remove_all(out.dir / stale);
  else if (!previous.is_null() && previous != request)
    throw std::invalid_argument("style " + name + " of " + run.root.string() + " was started with other settings (" +
                                out.dir.string() + "/request.json); pass --restart to train it again, or another --name");
  fs::create_directories(out.dir);
  util::write_file_atomic(out.dir / "request.json", request.dump(2) + "\n");

  // Stage 3.
  stylize::StylizeSettings settings{.strength = req.config.strength, .seed = req.config.seed};
  const nlohmann::json key = {{"stylizer", stylizer->name()}, {"strength", req.config.strength}, {"seed", req.config.seed},
                              {"style_image", request.at("style_image")}, {"network", network}};
  const style::StylizedFrames frames = style::stylize_dataset(run.dataset, *stylizer, style_image, settings, key, out.dir / "stylized");

  // Stage 4.
  nlohmann::json stage4;
  fs::path eval_dir = out.dir / "eval";
  if (req.config.method == run::StyleMethod::scratch) {
    write_dataset_layout(run.dataset, out.dir / "stylized");
    const fs::path scratch = out.dir / "run";
    std::unique_ptr<train::Trainer> trainer = fs::exists(scratch / "run.json")
                                                  ? train::Trainer::resume(ctx, scratch)
                                                  : std::make_unique<train::Trainer>(ctx, out.dir / "stylized", run.config, scratch);
    const train::TrainResult r = trainer->run(stop);
    if (!r.complete) return out;
    run::StyleFile file;
    file.method = run::StyleMethod::scratch;
    file.settings = style::to_json(req.config);
    file.count = r.num_gaussians;
    run::write_style_file(run::style_file_path(run.root, name), file);
    stage4 = {{"seconds", r.seconds}, {"test_psnr_vs_stylized", r.test.psnr}, {"test_ssim_vs_stylized", r.test.ssim}};
    eval_dir = scratch / "eval";
  } else {
    style::StyleTrainer trainer(ctx, run, frames.dataset, name, req.config);
    const style::StyleResult r = trainer.run(stop);
    if (!r.complete) return out;
    stage4 = {{"seconds", r.seconds}, {"iterations", r.iteration}, {"test_psnr_vs_stylized", r.test.psnr},
              {"test_ssim_vs_stylized", r.test.ssim}, {"stylized_gaussians", r.stylized_gaussians}};
  }

  // What the result looks like and how consistent it is.
  const scene::TrainedRun with_style = scene::read_trained_run(req.run);  // now lists the new style
  const int spiral = req.spiral_frames > 0 ? req.spiral_frames : static_cast<int>(std::max<size_t>(2, frames_per_camera(run.dataset)));
  const nlohmann::json consistency =
      spiral_consistency(ctx, with_style, name, out.dir, spiral, *stylizer, style_image, settings);
  double stylized_2d = 0, content_2d = 0;
  for (const auto& s : frames.sequences) stylized_2d += s.stylized_warp_error, content_2d += s.content_warp_error;
  const double sequences = static_cast<double>(std::max<size_t>(1, frames.sequences.size()));
  stylized_2d /= sequences, content_2d /= sequences;
  write_contact_sheet(run, frames.dataset, eval_dir, out.dir / "contact_sheet.png");
  const nlohmann::json test_camera = test_camera_consistency(run, frames.dataset, eval_dir);

  out.complete = true;
  out.summary = {{"style", name},
                 {"run", fs::absolute(run.root).string()},
                 {"method", run::method_name(req.config.method)},
                 {"stylizer", stylizer->name()},
                 {"style_image", request.at("style_image")},
                 {"stage3", frames.to_json()},
                 {"stage4", stage4},
                 {"warp_error", {{"spiral_styled_render", consistency.at("styled_render")},
                                 {"spiral_original_render", consistency.at("original_render")},
                                 {"spiral_stylized_2d", consistency.at("stylized_2d")},
                                 {"spiral_exact_flow", consistency.at("exact_flow")},
                                 {"stylized_frames_2d", stylized_2d},
                                 {"content_frames", content_2d},
                                 {"spiral_frames", spiral},
                                 {"test_camera", test_camera}}},
                 {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()},
                 {"device", ctx.info().name},
                 {"device_peak_mib", static_cast<double>(ctx.memory_peak()) / (1 << 20)},
                 {"settings", style::to_json(req.config)}};
  util::write_file_atomic(out.dir / "stylize.json", out.summary.dump(2) + "\n");
  return out;
}

}  // namespace s4d::cli
