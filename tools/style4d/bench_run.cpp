// style4d bench --run RUN --style NAME ... --out DIR: renders the run's test (fixed-view) and spiral
// protocols for the original scene and each style into DIR/renders/<source>/{test,spiral}, then
// scores them with the frames mode's evaluation (bench/report) and writes the run report.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "bench_ground_truth.h"
#include "bench_modes.h"
#include "s4d/bench/frames_eval.h"
#include "s4d/bench/pyiqa_bridge.h"
#include "s4d/bench/run_report.h"
#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/protocols/protocol_render.h"
#include "s4d/run/style_file.h"
#include "s4d/scene/trained_run.h"
#include "style_args.h"

namespace s4d::cli {

namespace fs = std::filesystem;

namespace {

struct Method {
  std::string name;  // a style of the run, or "original"
  fs::path style_image;
  std::string style;  // the report's style column: the image's file name without extension
};

// The style image a style was trained with, as a Method's image and label: its copy in the style's
// folder (run::style_image_path) labelled with the file name request.json records, or (a style from
// before the copy was kept) the file request.json names (s4d/style_gaussians/stylize_run.h).
std::pair<fs::path, std::string> requested_style_image(const fs::path& run, const std::string& style) {
  const fs::path file = run::style_dir(run, style) / "request.json";
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": missing; it names the style image (or pass --style-image S)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": not valid JSON (" + e.what() + "); pass --style-image S");
  }
  const auto* path = j.contains("style_image") && j["style_image"].is_object() && j["style_image"].contains("path")
                         ? &j["style_image"]["path"]
                         : nullptr;
  if (!path || !path->is_string())
    throw std::runtime_error(file.string() + ": no string field style_image.path; pass --style-image S");
  const fs::path image = path->get<std::string>();
  if (const fs::path copy = run::style_image_path(run, style); fs::exists(copy)) return {copy, image.stem().string()};
  if (!fs::exists(image))
    throw std::runtime_error(file.string() + ": style_image.path " + image.string() + " no longer exists (the style predates " +
                             run::style_image_path(run, style).filename().string() + " copies); pass --style-image S");
  return {image, image.stem().string()};
}

std::vector<Method> methods_of(const Args& args, const scene::TrainedRun& run) {
  const std::vector<std::string> names = args.get_all("style");
  if (names.empty()) {
    std::string known;
    for (const std::string& s : run.styles) known += (known.empty() ? "" : ", ") + s;
    throw UsageError("missing required option --style: give one or more of " + run.root.string() + "'s styles (" +
                                known + ")");
  }
  std::vector<Method> out;
  for (const std::string& name : names) {
    for (const Method& m : out)
      if (m.name == name) throw UsageError("--style " + name + ": given twice");
    if (std::find(run.styles.begin(), run.styles.end(), name) == run.styles.end()) {
      std::string known;
      for (const std::string& s : run.styles) known += (known.empty() ? "" : ", ") + s;
      throw UsageError("--style " + name + ": no style " + name + " in " + run.root.string() + " (no " +
                                  run::style_file_path(run.root, name).string() + "); it has: " + known +
                                  " (train one with style4d stylize --run " + run.root.string() + " --style IMG --name " + name + ")");
    }
    Method m{name, {}, "none"};
    if (name != "original" && args.get("style-image")) {
      m.style_image = *args.get("style-image");
      m.style = m.style_image.stem().string();
    } else if (name != "original") {
      std::tie(m.style_image, m.style) = requested_style_image(run.root, name);
    }
    if (!m.style_image.empty()) io::read_png(m.style_image);  // fails naming the file when it is missing or not a PNG
    out.push_back(std::move(m));
  }
  return out;
}

// Renders one source's two protocols into DIR/renders/<source>/{test,spiral}, redone on every call.
void render_source(engine::Context& ctx, const scene::TrainedRun& run, const std::string& source, const fs::path& dir,
                   const std::vector<protocols::Sequence>& test, const std::vector<protocols::Sequence>& spiral, bool flow,
                   splat::Storage storage) {
  fs::remove_all(dir);
  const std::unique_ptr<scene::SceneSource> scene = scene::open_scene(ctx, run, source, storage);
  protocols::RenderOptions options;
  options.background = run.dataset.background;
  options.flow = flow;
  std::cerr << "bench: rendering " << scene->describe() << " (test: " << test.size() << " camera(s); spiral: "
            << spiral.front().frames.size() << " frames)\n";
  protocols::render_protocol(ctx, *scene, protocols::parse_path("test"), test, dir / "test", options);
  protocols::render_protocol(ctx, *scene, protocols::parse_path("spiral"), spiral, dir / "spiral", options);
}

// Frames-mode options for one sequence: its original render, ground truth, exact flow folders and
// the method's style image.
bench::FramesOptions sequence_options(bench::FramesOptions o, const fs::path& original, const std::optional<fs::path>& truth,
                                      const fs::path& style_image = {}) {
  o.original = original;
  o.ground_truth = truth;
  o.flow_dir = original / "flow";
  o.style_image = style_image;
  return o;
}

}  // namespace

int bench_run(const Args& args, bench::FramesOptions options) {
  for (const char* o : {"stylized", "name", "original", "ground-truth", "flow-dir"})
    if (args.get(o))
      throw UsageError(std::string("--") + o + " belongs to the frames mode (--stylized); --run renders the original scene, "
                                  "its ground truth and its exact flow itself");
  const fs::path out = args.require("out"), renders = out / "renders";
  const int spiral_frames = parse_number<int>("spiral-frames", args.get_or("spiral-frames", std::to_string(protocols::kDefaultSpiralFrames)));
  if (spiral_frames < 2) throw UsageError("--spiral-frames: expected at least 2 (the warp loss needs a pair), got " +
                                                     std::to_string(spiral_frames));
  const scene::TrainedRun run = scene::read_trained_run(args.require("run"));
  const std::vector<Method> methods = methods_of(args, run);
  const std::vector<protocols::Sequence> test = protocols::build_protocol(run.dataset, protocols::parse_path("test"), spiral_frames);
  const std::vector<protocols::Sequence> spiral = protocols::build_protocol(run.dataset, protocols::parse_path("spiral"), spiral_frames);

  engine::Context ctx;
  // Weights and bridge options are checked before the renders, which take minutes.
  std::optional<bench::NativeLearned> learned;
  if (const auto lo = learned_options(args)) {
    learned.emplace(ctx, *lo);
    options.learned = &*learned;
  }
  const std::optional<bench::BridgeOptions> bridge = bridge_options(args, out, options.learned);
  // The original is always rendered: it is every method's content reference and carries the flow.
  const splat::Storage storage = parse_storage(args);
  render_source(ctx, run, "original", renders / "original", test, spiral, options.flow == bench::FlowSource::exact,
                storage);
  for (const Method& m : methods)
    if (m.name != "original") render_source(ctx, run, m.name, renders / m.name, test, spiral, false, storage);
  fs::remove_all(renders / "ground_truth");
  const std::optional<std::string> no_truth = write_ground_truth(run.dataset, test, renders / "ground_truth" / "test");

  // Each native learned metric on the protocol its headline comes from (run_report.h): dists on the
  // spiral, the others on the test cameras (each VGG pass costs seconds on a CPU device).
  std::vector<std::string> test_learned, spiral_learned;
  for (const std::string& k : bench::native_learned_keys())
    (bench::metric_protocol(k) == bench::Protocol::spiral ? spiral_learned : test_learned).push_back(k);
  const auto spiral_options = [&](const fs::path& style_image) {
    bench::FramesOptions o = sequence_options(options, renders / "original" / "spiral", std::nullopt, style_image);
    o.learned_keys = spiral_learned;
    return o;
  };
  options.learned_keys = test_learned;
  std::vector<std::vector<bench::MethodResult>> cameras(methods.size());
  std::vector<bench::MethodResult> spirals;
  for (size_t i = 0; i < methods.size(); ++i) {
    const Method& m = methods[i];
    std::cerr << "bench: scoring " << m.name << "\n";
    for (const protocols::Sequence& seq : test) {
      const auto truth = no_truth ? std::nullopt : std::optional<fs::path>(renders / "ground_truth" / "test" / seq.name);
      cameras[i].push_back(bench::evaluate_frames(m.name, renders / m.name / "test" / seq.name,
                                                  sequence_options(options, renders / "original" / "test" / seq.name, truth,
                                                                   m.style_image)));
      // Only the original's row has a psnr to miss; a style's row keeps "per run, not per style".
      if (no_truth) {
        std::string& reason = cameras[i].back().unavailable["psnr"];
        if (reason != bench::kPsnrPerRun) reason = *no_truth;
      }
    }
    spirals.push_back(bench::evaluate_frames(m.name, renders / m.name / "spiral", spiral_options(m.style_image)));
    spirals.back().unavailable["psnr"] = "the spiral path has no captured frames; psnr is scored on the test protocol";
  }
  if (bridge) {
    // One process for every sequence: each test camera's video for the test-protocol keys, the
    // spiral for dists (run_report.h's protocols).
    std::vector<bench::BridgeSequence> seqs;
    std::vector<std::string> test_keys, spiral_keys;
    for (const std::string& k : bridge->metrics)
      (bench::metric_protocol(k) == bench::Protocol::spiral ? spiral_keys : test_keys).push_back(k);
    const fs::path decoded = bridge->work_dir / "frames";
    for (size_t i = 0; i < methods.size(); ++i) {
      const fs::path style = methods[i].style_image.empty() ? fs::path() : fs::absolute(methods[i].style_image);
      // ckdn compares with the style image: the unstylised original has none.
      std::vector<std::string> keys = test_keys;
      if (style.empty() && std::erase(keys, "ckdn") != 0)
        for (bench::MethodResult& cam : cameras[i]) cam.unavailable["ckdn"] = "no style image: this method is the unstylised original scene";
      for (size_t c = 0; c < test.size() && !keys.empty(); ++c)
        seqs.push_back({methods[i].name + "/test/" + test[c].name,
                        bench::frame_files(renders / methods[i].name / "test" / test[c].name, decoded), style, keys});
      if (!spiral_keys.empty())
        seqs.push_back({methods[i].name + "/spiral", bench::frame_files(renders / methods[i].name / "spiral", decoded), style,
                        spiral_keys});
    }
    std::cerr << "bench: running the pyiqa bridge (" << bridge->python.string() << ") on " << seqs.size() << " sequence(s)\n";
    const bench::BridgeOutcome outcome = bench::run_bridge(*bridge, seqs);
    for (size_t i = 0; i < methods.size(); ++i) {
      for (size_t c = 0; c < test.size(); ++c)
        bench::apply_bridge(outcome, methods[i].name + "/test/" + test[c].name, test_keys, cameras[i][c]);
      bench::apply_bridge(outcome, methods[i].name + "/spiral", spiral_keys, spirals[i]);
    }
    for (const std::string& k : bridge->metrics) options.bridged[k] = bench::bridge_impl(*bridge, outcome, k);
  }
  std::vector<bench::RunMethodResult> results;
  for (size_t i = 0; i < methods.size(); ++i) {
    const Method& m = methods[i];
    bench::RunMethodResult r{bench::pool_sequences(m.name, cameras[i]), std::move(spirals[i]),
                             m.style, m.style_image};
    r.test.frames = renders / m.name / "test";
    results.push_back(std::move(r));
  }
  const bench::RunReportContext context{args.get_or("scene", fs::weakly_canonical(run.root).filename().string()), run.root,
                                        renders, spiral_frames,
                                        sequence_options(options, renders / "original" / "spiral", std::nullopt)};
  bench::write_run_report(out, results, context);
  std::cerr << "bench: wrote " << (out / "report.json").string() << ", report.md, report.csv, plots/, contact_sheet.png\n";
  return 0;
}

}  // namespace s4d::cli
