// style4d bench: Style4D-Bench. Frames mode, --frames A [--name N] [--frames A2 --name N2 ...]
// --original B --style-image S --out DIR, scores frames another program made; run mode, --run RUN
// --style NAME [--style NAME2 ...] --out DIR, renders a trained run's styles first (bench_run.cpp);
// merge, --merge DIR1 DIR2 ... --out DIR, puts the reports of a sweep's jobs in one table.
// The weight-free metrics are computed; every learned metric is reported as {"unavailable": ...}
// naming the weights it needs.
#include <iostream>
#include <stdexcept>

#include "args.h"
#include "bench_modes.h"
#include "commands.h"
#include "s4d/bench/frames_report.h"
#include "s4d/bench/merge_report.h"

namespace s4d::cli {

namespace {

const std::vector<OptionSpec> kSpecs = {
    {"frames", "stylised frames: a folder of PNGs or a video (.mp4); repeat for several methods", true, "A"},
    {"name", "method label for the matching --frames (default: its file name); repeat in the same order", true, "NAME"},
    {"original", "original-scene render of the same cameras and times (PNG folder or video)", true, "B"},
    {"style-image", "the style image the methods were given (--run: default each style's request.json)", true, "S"},
    {"out", "report folder: report.json, report.md, report.csv, plots/, contact_sheet.png", true, "DIR"},
    {"scene", "scene label (default: the --original file name; --run: the run folder's name)", true, "NAME"},
    {"ground-truth", "captured frames matching --original; enables psnr", true, "C"},
    {"uiqm", "UIQM variant: a (FUnIE-GAN, default) or b (xueleichen)", true, "a|b"},
    {"warp-norm", "warp loss per-pixel error: l1 (Style4D, default) or l2 (Lai et al.)", true, "l1|l2"},
    {"flow", "flow for the warp loss: dis (OpenCV; frames mode's default), raft (--raft), exact (--flow-dir; run mode's "
             "default, rendered with the original scene)", true, "SOURCE"},
    {"flow-on", "frames the flow is computed on: original (default) or stylized", true, "WHICH"},
    {"raft", "RAFT exported to ONNX (with --flow raft)", true, "FILE"},
    {"raft-inputs", "the ONNX graph's two input names (default image1,image2)", true, "A,B"},
    {"flow-dir", "exact flow: fw_NNNN.exr and bw_NNNN.exr (channels u, v in pixels) per pair", true, "DIR"},
    {"python", "Python with pyiqa for the learned metrics (the bridge is not built yet)", true, "EXE"},
    {"run", "run mode: a trained run, rendered along the test and spiral protocols", true, "RUN"},
    {"style", "a style of --run (style4d stylize --name), or original; repeat for several methods", true, "NAME"},
    {"spiral-frames", "run mode: frames of the spiral video (default 120)", true, "N"},
    {"merge", "merge mode: report folders (or their report.json) of earlier benches, one per job", true, "DIR..."},
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
  throw std::invalid_argument("--" + option + ": expected one of " + names + ", got '" + *v + "'");
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
      throw std::invalid_argument("--raft-inputs: expected two names separated by a comma, got '" + *names + "'");
    o.raft_inputs = {names->substr(0, comma), names->substr(comma + 1)};
  }
  return o;
}

}  // namespace

int cmd_bench(const std::vector<std::string>& argv) {
  const Args args(argv, kSpecs);
  if (args.help()) {
    std::cout << usage("bench",
                       "--frames A [--name N ...] --original B --style-image S --out DIR | --run RUN --style NAME "
                       "[--style NAME2 ...] --out DIR | --merge DIR1 DIR2 ... --out DIR",
                       "Style4D-Bench. Frames mode: the weight-free metrics (uiqm, content_ssim, warp_loss, psnr with "
                       "--ground-truth) of each --frames video against --original. Run mode: renders RUN's test and "
                       "spiral protocols for the original scene and each --style into DIR/renders and scores them the "
                       "same way (warp_loss on the spiral, the rest on the test cameras). Merge: one table from the "
                       "report.json of several runs of bench (a sweep's jobs). Learned metrics are reported as "
                       "unavailable with the weights they need (METRICS.md).",
                       kSpecs);
    return 0;
  }
  if (args.get("python"))
    throw std::invalid_argument("--python: the pyiqa bridge is not built yet; the learned metrics are reported as unavailable");
  if (args.get("merge")) {
    for (const char* o : {"run", "frames"})
      if (args.get(o)) throw std::invalid_argument(std::string("--merge reads finished reports; --") + o + " belongs to another mode");
    std::vector<std::filesystem::path> reports;
    // --merge A B C (a shell glob) and --merge A --merge B both work.
    for (const std::string& r : args.get_all("merge")) reports.emplace_back(r);
    for (const std::string& r : args.positionals()) reports.emplace_back(r);
    const std::filesystem::path out = args.require("out");
    bench::write_merged_report(out, bench::merge_reports(reports));
    std::cerr << "bench: merged " << reports.size() << " report(s) into " << (out / "report.json").string() << ", report.md, report.csv\n";
    return 0;
  }
  if (!args.positionals().empty()) throw std::invalid_argument("unexpected argument '" + args.positionals().front() + "'");
  if (args.get("run")) return bench_run(args, options_from(args, bench::FlowSource::exact));
  for (const char* o : {"style", "spiral-frames"})
    if (args.get(o)) throw std::invalid_argument(std::string("--") + o + " belongs to the --run mode");
  const std::vector<std::string> frames = args.get_all("frames"), names = args.get_all("name");
  if (frames.empty()) throw std::invalid_argument("missing required option --frames (see --help)");
  if (!names.empty() && names.size() != frames.size())
    throw std::invalid_argument("--name: given " + std::to_string(names.size()) + " times for " + std::to_string(frames.size()) +
                                " --frames; give one per --frames, in the same order, or none");
  const std::filesystem::path out = args.require("out"), style_image = args.require("style-image");
  io::read_png(style_image);  // fails naming the file when it is missing or not a PNG
  bench::ReportContext context{args.get_or("scene", ""), style_image.stem().string(), style_image,
                               options_from(args, bench::FlowSource::dis)};
  context.options.original = args.require("original");
  if (auto gt = args.get("ground-truth")) context.options.ground_truth = *gt;
  if (context.options.flow == bench::FlowSource::exact) context.options.flow_dir = args.require("flow-dir");
  if (context.scene.empty()) context.scene = context.options.original.filename().string();

  std::vector<bench::MethodResult> results;
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::string name = names.empty() ? std::filesystem::path(frames[i]).filename().string() : names[i];
    std::cerr << "bench: scoring " << name << " (" << frames[i] << ")\n";
    results.push_back(bench::evaluate_frames(name, frames[i], context.options));
  }
  bench::write_frames_report(out, results, context);
  std::cerr << "bench: wrote " << (out / "report.json").string() << ", report.md, report.csv, plots/, contact_sheet.png\n";
  return 0;
}

}  // namespace s4d::cli
