// style4d render --run RUN --path test|spiral|train:CAM|FILE.json --out DIR: a trained run along a
// render protocol or a camera path (bench/protocols), with its frames.json, optional exact flow, and
// DIR/render.json.
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "device_json.h"
#include "render_modes.h"
#include "s4d/engine/context.h"
#include "s4d/protocols/protocol.h"
#include "s4d/protocols/protocol_render.h"
#include "s4d/scene/trained_run.h"
#include "s4d/util/atomic_file.h"
#include "style_args.h"

namespace s4d::cli {

int render_run(const Args& args) {
  for (const char* o : {"ply", "cameras", "sh-degree", "size"})
    if (args.get(o)) throw UsageError(std::string("--") + o + " belongs to the --ply mode, not --run");
  const std::filesystem::path run = args.require("run"), out = args.require("out");
  protocols::PathSpec path;
  try {
    path = protocols::parse_path(args.require("path"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  protocols::RenderOptions options;
  options.format = protocols::parse_format(args.get_or("format", "png"));
  options.flow = args.flag("flow");
  if (args.get("spiral-frames") && path.kind != protocols::PathSpec::Kind::spiral)
    throw UsageError("--spiral-frames sets the spiral's length; test, train:CAM and a path file render at their own times");
  const int frames =
      parse_number<int>("spiral-frames", args.get_or("spiral-frames", std::to_string(protocols::kDefaultSpiralFrames)));
  if (frames < 1) throw UsageError("--spiral-frames: expected at least 1, got " + std::to_string(frames));

  const auto start = std::chrono::steady_clock::now();
  engine::Context ctx;
  const scene::TrainedRun trained = scene::read_trained_run(run);
  const scene::StyleChoice choice = parse_style_choice(args);
  const splat::Storage storage = parse_storage(args);
  const std::unique_ptr<scene::SceneSource> source = scene::open_scene(ctx, trained, choice, storage);
  options.background = args.get("background") ? parse_background(*args.get("background")) : trained.dataset.background;
  const std::vector<protocols::Sequence> sequences = protocols::build_protocol(trained.dataset, path, frames);
  std::cerr << "[render] " << source->describe() << "; path " << path.text() << ": " << sequences.size()
            << " sequence(s)\n";
  const protocols::ProtocolResult result = protocols::render_protocol(ctx, *source, path, sequences, out, options);

  nlohmann::json seqs = nlohmann::json::array();
  int total = 0;
  for (size_t s = 0; s < result.stats.size(); ++s) {
    const protocols::SequenceStats& st = result.stats[s];
    const protocols::SequenceRecord& rec = result.record.sequences[s];
    total += st.frames;
    seqs.push_back({{"name", st.name},
                    {"dir", rec.dir},
                    {"frames", st.frames},
                    {"time_first", rec.sequence.frames.front().time},
                    {"time_last", rec.sequence.frames.back().time},
                    {"width", rec.sequence.frames.front().camera.width},
                    {"height", rec.sequence.frames.front().camera.height},
                    {"ms_render_per_frame", st.ms_render},
                    {"ms_flow_per_frame", st.ms_flow},
                    {"max_instances", st.max_instances}});
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const nlohmann::json summary = {{"run", std::filesystem::absolute(run).string()},
                                  {"style", args.get("style") ? nlohmann::json(*args.get("style")) : nlohmann::json()},
                                  {"mix", choice.mix.empty() ? nlohmann::json() : nlohmann::json(choice.mix)},
                                  {"alpha", choice.mix.empty() ? nlohmann::json() : nlohmann::json(choice.alpha)},
                                  {"stage", run::geometry_name(trained.stage)},
                                  {"scene", source->describe()},
                                  {"data", trained.dataset.root.string()},
                                  {"path", path.text()},
                                  {"format", protocols::format_name(options.format)},
                                  {"flow", options.flow},
                                  {"background", options.background},
                                  {"frames", total},
                                  {"seconds", seconds},
                                  {"storage", storage_json(storage, source->sh_style_bytes(), ctx)},
                                  {"device", device_json(ctx.info())},
                                  {"sequences", seqs}};
  util::write_file_atomic(out / "render.json", summary.dump(2) + "\n");
  std::cout << "rendered " << total << " frames (" << path.text() << ") into " << out.string() << "\n";
  return 0;
}

}  // namespace s4d::cli
