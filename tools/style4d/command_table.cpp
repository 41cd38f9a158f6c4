#include "commands.h"

namespace s4d::cli {

const std::vector<Command>& command_table() {
  static const std::vector<Command> list = {
      {"synth", "render the built-in synthetic dynamic scene into a DyNeRF/Neu3D dataset (CPU)", cmd_synth},
      {"check-data", "check a dataset: layout, cameras, frames, times, bounds, and every problem by file and field",
       cmd_check_data},
      {"devices", "list Vulkan devices and the features the engine uses", cmd_devices},
      {"train", "train Gaussians on a dataset (static Gaussians, then 4DGS), with checkpoints and --resume",
       cmd_train},
      {"view", "the real-time viewer of a trained run (or --screenshot: one frame, no window)", cmd_view},
      {"render", "render a trained run along a protocol, or a 3DGS PLY from NeRF-style cameras", cmd_render},
      {"export-ply", "a trained run's Gaussians at time t (4DGS: deformed) as a standard 3DGS PLY",
       cmd_export_ply},
      {"stylize", "stages 3 and 4: stylize a trained run after a style image (Style Gaussians), with --method ablations",
       cmd_stylize},
      {"stylize-frames", "restyle one camera's frames (folder or video) after a style image", cmd_stylize_frames},
      {"make-style", "write the built-in procedural style image", cmd_make_style},
      {"train-stylizer", "train the MCCNet/HGST decoder and MCC module (VGG-19 fixed) into a --weights folder",
       cmd_train_stylizer},
      {"bench", "Style4D-Bench metrics of stylised frames against the original render (report.json, .md, .csv, plots)",
       cmd_bench},
      {"sweep", "a benchmark sweep (scenes x styles x methods) as cells: plan, run on Slurm or locally, status, merged table",
       cmd_sweep},
      {"study", "the user study: plan pairs from bench outputs, serve them to participants, report the vote shares",
       cmd_study},
      {"demo", "run the whole pipeline on the built-in scene and style, with a report", cmd_demo},
  };
  return list;
}

const Command* find_command(const std::string& name) {
  for (const Command& c : command_table())
    if (name == c.name) return &c;
  return nullptr;
}

}  // namespace s4d::cli
