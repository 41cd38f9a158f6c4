// style4d bench: Style4D-Bench. Frames mode, --stylized A [--name N] [--stylized A2 --name N2 ...]
// --original B --style-image S --out DIR, scores frames another program made; run mode, --run RUN
// --style NAME [--style NAME2 ...] --out DIR, renders a trained run's styles first (bench_run.cpp);
// merge, --merge DIR1 DIR2 ... --out DIR, puts the reports of a sweep's jobs in one table.
// The weight-free metrics are computed; the native learned ones (LPIPS, DISTS, Gram loss, DINO, CKDN, MUSIQ) with
// --metric-weights DIR; the others through the pyiqa bridge (--python); any learned metric left is
// reported as {"unavailable": ...} naming what it needs.
#include <algorithm>
#include <iostream>
#include <stdexcept>

#include "args.h"
#include "bench_modes.h"
#include "commands.h"
#include "s4d/bench/frames_report.h"
#include "s4d/bench/merge_report.h"
#include "s4d/bench/native_learned.h"
#include "s4d/engine/context.h"
#include "style_args.h"

namespace s4d::cli {

namespace {

const std::vector<OptionSpec> kSpecs = {
    group("frames mode"),
    {"stylized", "stylised frames: a folder of PNGs or a video (.mp4); repeat for several methods", true, "A", {"frames"}},
    {"name", "method label for the matching --stylized (default: its file name); repeat in the same order", true, "NAME"},
    {"original", "original-scene render of the same cameras and times (PNG folder or video)", true, "B"},
    {"style-image", "the style image the methods were given (--run: default the copy each style keeps, RUN/style/NAME/style_image.png)", true, "S"},
    {"out", "report folder: report.json, report.md, report.csv, plots/, contact_sheet.png (every mode)", true, "DIR"},
    {"scene", "scene label (default: the --original file name; --run: the run folder's name)", true, "NAME"},
    {"ground-truth", "captured frames matching --original; enables psnr", true, "C"},
    group("metrics"),
    {"uiqm", "UIQM variant: a (FUnIE-GAN, default) or b (xueleichen)", true, "a|b"},
    {"warp-norm", "warp loss per-pixel error: l1 (Style4D, default) or l2 (Lai et al.)", true, "l1|l2"},
    {"flow", "flow for the warp loss: dis (OpenCV; frames mode's default), raft (--raft), exact (--flow-dir; run mode's "
             "default, rendered with the original scene)", true, "SOURCE"},
    {"flow-on", "frames the flow is computed on: original (default) or stylized", true, "WHICH"},
    {"raft", "RAFT exported to ONNX (with --flow raft)", true, "FILE"},
    {"raft-inputs", "the ONNX graph's two input names (default image1,image2)", true, "A,B"},
    {"flow-dir", "exact flow: fw_NNNN.exr and bw_NNNN.exr (channels u, v in pixels) per pair", true, "DIR"},
    {"metric-weights", "folder of safetensors weights for the native learned metrics: vgg16, lpips_vgg (content_lpips, "
                       "style_lpips), dists, vgg_normalised or vgg19 (style_loss_gram), dino_vitb16 (dino_score), ckdn, "
                       "musiq, musiq_paq2piq, written from the published "
                       "checkpoints by tools/convert_weights.py; docs/bench.md, \"Learned metrics\"", true, "DIR"},
    {"gram-vgg", "VGG19 of style_loss_gram: normalised (AdaIN vgg_normalised.safetensors, default) or torchvision "
                 "(vgg19.safetensors)", true, "WHICH"},
    {"lpips-net", "backbone of content_lpips and style_lpips: vgg (vgg16 + lpips_vgg, default) or alex (alexnet + "
                  "lpips_alex)", true, "NET"},
    {"lpips-input", "what LPIPS's scaling layer gets: standard (2x - 1 of the [0,1] frame: richzhang lpips, pyiqa; "
                    "default) or 3dgs (the [0,1] frame as is: the 3DGS lpipsPyTorch of the Style4D authors' metrics.py)",
     true, "WHICH"},
    {"python", "a Python with pyiqa: computes clipiqa_plus, musiq, qalign, musiq_paq2piq, dists, dino_score, ckdn through "
               "the pyiqa bridge (OUT/bridge: request.json, response.json, bridge.log)", true, "PY"},
    {"bridge-script", "the bridge script to run instead of the embedded tools/pyiqa_bridge.py (same protocol)", true, "FILE"},
    {"bridge-metrics", "the keys to ask the bridge for, comma-separated (default: all seven)", true, "LIST"},
    group("run mode"),
    {"run", "a trained run, rendered along the test and spiral protocols", true, "RUN"},
    {"style", "a style of --run (style4d stylize --style), or original; repeat for several methods", true, "NAME"},
    {"spiral-frames", "run mode: frames of the spiral video (default 120)", true, "N"},
    half_spec(),
    group("merge mode"),
    {"merge", "report folders (or their report.json) of earlier benches, one per job", true, "DIR..."},
};

template <class T>
T choose(const Args& args, const std::string& option, const std::vector<std::pair<std::string, T>>& choices, T fallback) {
  const auto v = args.get(option);
  if (!v) return fallback;
  std::string names;
  for (const auto& [name, value] : choices) {
    if (*v == name) return value;
    names += (names.empty() ? "" : ", ") + name;
  }
  throw UsageError("--" + option + ": expected one of " + names + ", got '" + *v + "'");
}

// The scoring options both modes share; `flow` is the mode's default flow source.
bench::FramesOptions options_from(const Args& args, bench::FlowSource flow) {
  bench::FramesOptions o;
  o.uiqm = choose<metrics::UiqmVariant>(args, "uiqm", {{"a", metrics::UiqmVariant::a_funie}, {"b", metrics::UiqmVariant::b_xueleichen}},
                                        metrics::UiqmVariant::a_funie);
  o.warp_norm = choose<metrics::WarpNorm>(args, "warp-norm", {{"l1", metrics::WarpNorm::abs}, {"l2", metrics::WarpNorm::squared}},
                                          metrics::WarpNorm::abs);
  o.flow = choose<bench::FlowSource>(
      args, "flow", {{"dis", bench::FlowSource::dis}, {"raft", bench::FlowSource::raft}, {"exact", bench::FlowSource::exact}},
      flow);
  o.flow_on = choose<bench::FlowFrames>(args, "flow-on",
                                        {{"original", bench::FlowFrames::original}, {"stylized", bench::FlowFrames::stylized}},
                                        bench::FlowFrames::original);
  if (o.flow == bench::FlowSource::raft) o.raft_onnx = args.require("raft");
  if (auto names = args.get("raft-inputs")) {
    const size_t comma = names->find(',');
    if (comma == std::string::npos || comma == 0 || comma + 1 == names->size())
      throw UsageError("--raft-inputs: expected two names separated by a comma, got '" + *names + "'");
    o.raft_inputs = {names->substr(0, comma), names->substr(comma + 1)};
  }
  return o;
}

}  // namespace

std::optional<bench::BridgeOptions> bridge_options(const Args& args, const std::filesystem::path& out,
                                                   const bench::NativeLearned* learned) {
  const auto python = args.get("python");
  if (!python) {
    for (const char* o : {"bridge-script", "bridge-metrics"})
      if (args.get(o)) throw UsageError(std::string("--") + o + ": needs --python PY (the bridge's interpreter)");
    return std::nullopt;
  }
  bench::BridgeOptions b{*python, std::nullopt, out / "bridge", bench::bridge_keys()};
  if (auto script = args.get("bridge-script")) {
    if (!std::filesystem::is_regular_file(*script)) throw UsageError("--bridge-script " + *script + ": no such file");
    b.script = *script;
  }
  if (auto list = args.get("bridge-metrics")) {
    b.metrics.clear();
    std::string rest = *list;
    while (!rest.empty()) {
      const size_t comma = rest.find(',');
      const std::string key = rest.substr(0, comma);
      rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
      const auto& keys = bench::bridge_keys();
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
        std::string known;
        for (const std::string& k : keys) known += (known.empty() ? "" : ", ") + k;
        throw UsageError("--bridge-metrics: '" + key + "' is not a bridge key (" + known + ")");
      }
      if (std::find(b.metrics.begin(), b.metrics.end(), key) == b.metrics.end()) b.metrics.push_back(key);
    }
    if (b.metrics.empty()) throw UsageError("--bridge-metrics: empty list");
  }
  // A key the native networks compute is not asked of the bridge.
  std::erase_if(b.metrics, [&](const std::string& k) { return learned != nullptr && learned->computes(k); });
  if (b.metrics.empty()) return std::nullopt;
  return b;
}

std::optional<bench::NativeLearnedOptions> learned_options(const Args& args) {
  const auto gram = choose<metrics::GramBackbone>(
      args, "gram-vgg", {{"normalised", metrics::GramBackbone::vgg_normalised}, {"torchvision", metrics::GramBackbone::torchvision_vgg19}},
      metrics::GramBackbone::vgg_normalised);
  const auto dir = args.get("metric-weights");
  if (!dir) {
    for (const char* o : {"gram-vgg", "lpips-net", "lpips-input"})
      if (args.get(o)) throw UsageError(std::string("--") + o + ": needs --metric-weights DIR (the folder holding the network)");
    return std::nullopt;
  }
  const auto net = choose<metrics::LpipsNet>(args, "lpips-net", {{"vgg", metrics::LpipsNet::vgg}, {"alex", metrics::LpipsNet::alex}},
                                            metrics::LpipsNet::vgg);
  const auto input = choose<metrics::LpipsInput>(
      args, "lpips-input", {{"standard", metrics::LpipsInput::signed_unit}, {"3dgs", metrics::LpipsInput::unit}},
      metrics::LpipsInput::signed_unit);
  return bench::NativeLearnedOptions{std::filesystem::path(*dir), gram, net, input};
}

int cmd_bench(const std::vector<std::string>& argv) {
  const Args args(argv, kSpecs);
  if (args.help()) {
    std::cout << usage("bench",
                       "--stylized A [--name N ...] --original B --style-image S --out DIR | --run RUN --style NAME "
                       "[--style NAME2 ...] --out DIR | --merge DIR1 DIR2 ... --out DIR",
                       "Style4D-Bench. Frames mode: the weight-free metrics (uiqm, content_ssim, warp_loss, psnr with "
                       "--ground-truth) of each --stylized video against --original. Run mode: renders RUN's test and "
                       "spiral protocols for the original scene and each --style into DIR/renders and scores them the "
                       "same way (warp_loss on the spiral, the rest on the test cameras). Merge: one table from the "
                       "report.json of several runs of bench (a sweep's jobs). Learned metrics: content_lpips, "
                       "style_lpips, dists, style_loss_gram, dino_score, ckdn, musiq and musiq_paq2piq natively with "
                       "--metric-weights DIR, the others through the "
                       "pyiqa bridge with --python PY; any left are reported as unavailable, naming what to supply "
                       "(docs/bench.md, \"Learned metrics\").",
                       kSpecs);
    return 0;
  }
  if (args.get("merge")) {
    for (const char* o : {"run", "stylized"})
      if (args.get(o)) throw UsageError(std::string("--merge reads finished reports; --") + o + " belongs to another mode");
    std::vector<std::filesystem::path> reports;
    // --merge A B C (a shell glob) and --merge A --merge B both work.
    for (const std::string& r : args.get_all("merge")) reports.emplace_back(r);
    for (const std::string& r : args.positionals()) reports.emplace_back(r);
    const std::filesystem::path out = args.require("out");
    bench::write_merged_report(out, bench::merge_reports(reports));
    std::cerr << "bench: merged " << reports.size() << " report(s) into " << (out / "report.json").string() << ", report.md, report.csv\n";
    return 0;
  }
  if (!args.positionals().empty()) throw UsageError("unexpected argument '" + args.positionals().front() + "'");
  if (args.get("run")) return bench_run(args, options_from(args, bench::FlowSource::exact));
  for (const char* o : {"style", "spiral-frames"})
    if (args.get(o)) throw UsageError(std::string("--") + o + " belongs to the --run mode");
  if (args.flag("half")) throw UsageError("--half belongs to the --run mode (it renders the run)");
  const std::vector<std::string> frames = args.get_all("stylized"), names = args.get_all("name");
  if (frames.empty()) throw UsageError("missing required option --stylized (see --help)");
  if (!names.empty() && names.size() != frames.size())
    throw UsageError("--name: given " + std::to_string(names.size()) + " times for " + std::to_string(frames.size()) +
                                " --stylized; give one per --stylized, in the same order, or none");
  const std::filesystem::path out = args.require("out"), style_image = args.require("style-image");
  io::read_png(style_image);  // fails naming the file when it is missing or not a PNG
  bench::ReportContext context{args.get_or("scene", ""), style_image.stem().string(), style_image,
                               options_from(args, bench::FlowSource::dis)};
  context.options.original = args.require("original");
  if (auto gt = args.get("ground-truth")) context.options.ground_truth = *gt;
  if (context.options.flow == bench::FlowSource::exact) context.options.flow_dir = args.require("flow-dir");
  if (context.scene.empty()) context.scene = context.options.original.filename().string();

  context.options.style_image = style_image;
  std::optional<engine::Context> ctx;
  std::optional<bench::NativeLearned> learned;
  if (const auto lo = learned_options(args)) {
    ctx.emplace();
    learned.emplace(*ctx, *lo);
    context.options.learned = &*learned;
  }
  const std::optional<bench::BridgeOptions> bridge = bridge_options(args, out, context.options.learned);

  std::vector<bench::MethodResult> results;
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::string name = names.empty() ? std::filesystem::path(frames[i]).filename().string() : names[i];
    std::cerr << "bench: scoring " << name << " (" << frames[i] << ")\n";
    results.push_back(bench::evaluate_frames(name, frames[i], context.options));
  }
  if (bridge) {
    std::vector<bench::BridgeSequence> seqs;
    for (size_t i = 0; i < frames.size(); ++i)
      seqs.push_back({"method" + std::to_string(i), bench::frame_files(frames[i], bridge->work_dir / "frames" / std::to_string(i)),
                      std::filesystem::absolute(style_image), bridge->metrics});
    std::cerr << "bench: running the pyiqa bridge (" << bridge->python.string() << ") on " << seqs.size() << " method(s)\n";
    const bench::BridgeOutcome outcome = bench::run_bridge(*bridge, seqs);
    for (size_t i = 0; i < frames.size(); ++i) bench::apply_bridge(outcome, seqs[i].id, bridge->metrics, results[i]);
    for (const std::string& k : bridge->metrics) context.options.bridged[k] = bench::bridge_impl(*bridge, outcome, k);
  }
  bench::write_frames_report(out, results, context);
  std::cerr << "bench: wrote " << (out / "report.json").string() << ", report.md, report.csv, plots/, contact_sheet.png\n";
  return 0;
}

}  // namespace s4d::cli
