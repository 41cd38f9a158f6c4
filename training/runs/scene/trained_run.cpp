#include "s4d/scene/trained_run.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "s4d/io/ply_gaussians.h"
#include "s4d/run/run_dir.h"
#include "s4d/run/run_json.h"
#include "s4d/run/style_file.h"
#include "s4d/scene/deformed_scene.h"
#include "s4d/scene/static_scene.h"
#include "s4d/scene/style_blend.h"
#include "s4d/scene/styled_scene.h"
#include "s4d/scene/trained_field.h"

namespace s4d::scene {
namespace {

namespace fs = std::filesystem;

// The style file of `style`, one of run.styles other than "original".
run::StyleFile read_run_style(const TrainedRun& run, const std::string& style) {
  if (std::find(run.styles.begin(), run.styles.end(), style) == run.styles.end()) {
    std::string known;
    for (const std::string& s : run.styles) known += (known.empty() ? "" : ", ") + s;
    throw std::runtime_error("no style " + style + " in " + run.root.string() + "; it has: " + known +
                             " (train one with style4d stylize --run " + run.root.string() + " --style-image IMG)");
  }
  return run::read_style_file(run::style_file_path(run.root, style));
}

[[noreturn]] void incomplete(const fs::path& root, const std::vector<std::string>& missing, const std::string& fix) {
  std::string list;
  for (size_t i = 0; i < missing.size(); ++i) list += (i ? "; " : "") + missing[i];
  throw std::runtime_error(root.string() + " is an incomplete run: " + list + "; " + fix);
}

}  // namespace

TrainedRun read_trained_run(const fs::path& root) {
  const run::RunDir run{root};
  if (!fs::is_directory(root))
    throw std::runtime_error(root.string() + " is not a directory; train a run there with `style4d train --data DIR --run " +
                             root.string() + "`");
  // A folder of other files (a dataset, say) is not trained into: the run goes in a folder of its own.
  std::error_code ec;
  const bool run_files = fs::exists(run.train_json()) || fs::exists(run.checkpoint().parent_path()) ||
                         fs::exists(run.gaussians_ply().parent_path());
  if (!fs::exists(run.run_json()) && !run_files && !fs::is_empty(root, ec))
    throw std::runtime_error(root.string() + " is not a training run (no run.json); if it is a dataset, train a run from it "
                             "with `style4d train --data " + root.string() + " --run NEW_RUN_DIR`");
  if (!fs::exists(run.run_json()))
    incomplete(root, {run.run_json().string() + ": missing (what was trained from what)"},
               "train a run there with `style4d train --data DIR --run " + root.string() + "`");
  run::RunJson j = run::read_run_json(run);  // names the file and the field
  TrainedRun out;
  out.root = root;
  out.stage = j.stage.value_or(run::Stage::coarse);  // runs written before stages were named are static
  out.config = std::move(j.settings);

  std::vector<std::string> missing;
  if (out.stage == run::Stage::coarse && !fs::exists(run.gaussians_ply()))
    missing.push_back(run.gaussians_ply().string() + ": missing (the Gaussians, written at each checkpoint and at the end)");
  if (out.stage == run::Stage::fine && !fs::exists(run.checkpoint()))
    missing.push_back(run.checkpoint().string() +
                      ": missing (the canonical Gaussians and the deformation field, written at each checkpoint)");
  const fs::path data_path = j.data;
  const bool no_data = !fs::exists(data_path);
  if (no_data) missing.push_back(data_path.string() + ": missing (the dataset that run.json's field 'data' names)");
  // A finished run (train.json: complete) is not trained again: what it lost cannot be finished.
  std::ifstream train_json(run.train_json());
  const nlohmann::json train = nlohmann::json::parse(train_json, nullptr, false);
  const bool finished = train.is_object() && train.value("complete", false);
  if (!missing.empty())
    incomplete(root, missing,
               no_data && missing.size() == 1 ? "put the dataset back or correct 'data' in " + run.run_json().string()
               : finished ? "the run finished, and what is missing cannot be rebuilt from the rest; train a new run "
                            "with `style4d train --data DIR --run NEW_RUN_DIR`"
                          : "finish it with `style4d train --run " + root.string() + "`");
  data::LoadOptions load{.downscale = out.config.downscale, .background = out.config.background, .probe_background = false};
  if (!out.config.frames.empty()) load.frames = data::parse_frame_range(out.config.frames, run.run_json().string() + ": frames");
  out.dataset = data::load_dataset(data_path, load);
  if (out.dataset.views.empty()) throw std::runtime_error(data_path.string() + ": the dataset has no views");
  for (const std::string& name : run::list_styles(root)) out.styles.push_back(name);
  return out;
}

std::unique_ptr<SceneSource> open_scene(engine::Context& ctx, const TrainedRun& run, const std::string& style,
                                        splat::Storage storage) {
  if (style != "original") {
    const run::StyleFile file = read_run_style(run, style);
    if (file.method == run::StyleMethod::scratch)  // the ablation's own 4DGS run, trained on the stylized frames
      return open_scene(ctx, read_trained_run(run::style_dir(run.root, style) / "run"), "original", storage);
    return std::make_unique<StyledScene>(ctx, open_scene(ctx, run, "original", storage), file, style, storage);
  }
  const run::RunDir dir{run.root};
  const run::TrainConfig& c = run.config;
  if (run.stage == run::Stage::fine) {
    const TrainedField f = read_trained_field(dir.checkpoint(), c, run.root);
    return std::make_unique<DeformedScene>(ctx, f.canonical, f.field, f.planes, f.mlp, f.still_mask,
                                           run::active_sh_degree(c, c.iterations + f.fine_iteration), storage);
  }
  const io::GaussianCloud cloud = io::read_ply_gaussians(dir.gaussians_ply());
  if (cloud.size() == 0) throw std::runtime_error(dir.gaussians_ply().string() + ": no Gaussians");
  return std::make_unique<StaticScene>(ctx, cloud, run::active_sh_degree(c, c.iterations), "run gaussians", storage);
}

std::unique_ptr<BlendedScene> open_blend(engine::Context& ctx, const TrainedRun& run, const std::string& a,
                                         const std::string& b, float alpha, splat::Storage storage) {
  std::unique_ptr<SceneSource> base = open_scene(ctx, run, "original", storage);
  auto style_of = [&](const std::string& name) {
    if (name == "original") return no_style(base->size(), base->at(0.0, {}).sh_coeffs);
    run::StyleFile file = read_run_style(run, name);
    if (file.method == run::StyleMethod::scratch)
      throw std::invalid_argument("style " + name + " was trained with --method scratch: it is a run of its own (" +
                                  (run::style_dir(run.root, name) / "run").string() +
                                  "), not changes to this run's Gaussians, so it cannot be blended with another style");
    return file;
  };
  run::StyleFile file_a = style_of(a), file_b = style_of(b);
  try {
    return std::make_unique<BlendedScene>(ctx, std::move(base), std::move(file_a), a, std::move(file_b), b, alpha,
                                          storage);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("styles " + a + " and " + b + ": " + e.what());
  }
}

std::unique_ptr<SceneSource> open_scene(engine::Context& ctx, const TrainedRun& run, const StyleChoice& choice,
                                        splat::Storage storage) {
  if (choice.mix.empty()) return open_scene(ctx, run, choice.style, storage);
  return open_blend(ctx, run, choice.style, choice.mix, choice.alpha, storage);
}

}  // namespace s4d::scene
