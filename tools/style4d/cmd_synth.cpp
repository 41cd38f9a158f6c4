// style4d synth --out DIR [--cams N] [--frame-count T] [--size WxH] [--seed S] [--video]: renders the built-in
// dynamic scene with the independent CPU ray caster (s4d_synth) into a DyNeRF / Neu3D dataset.
#include <cstdint>
#include <iostream>
#include <stdexcept>
#include <tuple>

#include "args.h"
#include "commands.h"
#include "s4d/synth/dataset.h"
#include "s4d/util/progress.h"

namespace s4d::cli {

int cmd_synth(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"out", "output directory (must not exist, or be empty)", true, "DIR"},
      {"cams", "number of cameras on the arc, 2-99 (default 10)", true, "N"},
      {"frame-count", "number of frames, 2-9999 (default 30)", true, "T", {"frames"}},
      {"size", "image size, each side 8-4096 (default 160x120)", true, "WxH"},
      {"seed", "seed of the antialiasing jitter and the point sampling (default 0)", true, "S"},
      // Continuation lines are indented to the help column of usage().
      {"video", "write each camera as DIR/camNN.mp4 (MPEG-4 Part 2, fourcc mp4v, 30 fps) instead\n"
                "                        of DIR/camNN/NNNN.png. mp4v is LOSSY (8-bit, 4:2:0 chroma, about 1\n"
                "                        bit per pixel): decoded frames of this scene at 160x120 differ from\n"
                "                        the render by 6 levels of 255 on average and up to 160 at sharp\n"
                "                        edges. --size must be even on both sides", false, ""},
      {"dnerf", "write the D-NeRF layout, monocular: DIR/train/r_NNN.png one view per time, each\n"
                "                        from another camera of the arc (not camera 0), DIR/test/r_NNN.png\n"
                "                        camera 0 at every time, DIR/transforms_{train,test}.json", false, ""},
      {"object", "the moving objects alone on black (no wall or floor), cameras on a full ring\n"
                 "                        above them: with --dnerf, a D-NeRF-like object capture", false, ""},
      {"motion", "object fixture instead of the built-in objects (implies --object): bounce (three\n"
                 "                        small spheres collide and fly apart), squash (a sphere falls on a box,\n"
                 "                        squashes, rebounds), orbit (a finely checkered sphere on a full orbit)", true, "NAME"},
      {"rgba", "with --dnerf: RGBA frames with a transparent sky, as D-NeRF's (loaders composite\n"
               "                        them on white)", false, ""},
      {"mixed-distances", "cameras at 1, 1.4 and 0.75 times the rig's distance and 1, 1.2, 0.85 times\n"
                          "                        its focal length in turn (the test camera keeps the rig's)", false, ""},
      {"still", "every frame shows the scene at its first moment (times still run 0..1): a capture of\n"
                "                        a scene that does not move", false, ""},
      {"glossy", "surfaces carry a broad white highlight, so colours change with the viewpoint (view-\n"
                 "                        dependent shading, which higher SH degrees model)", false, ""},
      {"random-init", "write fused.ply with N uniform random points in [-1.3, 1.3]^3 (4DGaussians'\n"
                      "                        synthetic recipe) instead of points3D.ply's surface points", true, "N"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("synth", "--out DIR [--cams N] [--frame-count T] [--size WxH] [--seed S] [--video | --dnerf [--rgba]] [--object | --motion NAME]\n"
                       "       [--mixed-distances] [--random-init N] [--still] [--glossy]",
                       "Renders the built-in dynamic scene (static textured wall and floor, a spinning sphere,\n"
                       "a box sliding along an arc, a waving sheet) with an analytic CPU ray caster into a\n"
                       "DyNeRF/Neu3D dataset: DIR/camNN/NNNN.png (frame k has t = k/(T-1); DIR/camNN.mp4 with\n"
                       "--video), DIR/poses_bounds.npy (LLFF [N, 17]), DIR/points3D.ply (points at t = 0) and\n"
                       "DIR/scene.json. The files are written into DIR.partial, which becomes DIR only when\n"
                       "everything is written.",
                       specs);
    return 0;
  }
  if (!args.positionals().empty())
    throw UsageError("unexpected argument '" + args.positionals().front() + "'");
  synth::SynthOptions options;
  const std::string out = args.require("out");
  options.cams = parse_number<int>("cams", args.get_or("cams", "10"));
  options.frames = parse_number<int>("frame-count", args.get_or("frame-count", "30"));
  std::tie(options.width, options.height) = parse_size("size", args.get_or("size", "160x120"));
  options.seed = parse_number<uint64_t>("seed", args.get_or("seed", "0"));
  options.video = args.flag("video");
  options.dnerf = args.flag("dnerf");
  options.object = args.flag("object");
  options.motion = args.get_or("motion", "");
  options.rgba = args.flag("rgba");
  options.mixed_distances = args.flag("mixed-distances");
  options.random_init = parse_number<int>("random-init", args.get_or("random-init", "0"));
  options.still = args.flag("still");
  options.glossy = args.flag("glossy");
  try {
    synth::check_options(options);
  } catch (const std::invalid_argument& e) {  // a flag out of its range
    throw UsageError(e.what());
  }

  util::Progress progress("synth", static_cast<uint64_t>(options.cams) * static_cast<uint64_t>(options.frames));
  synth::write_dataset(out, options, [&](uint64_t done, uint64_t) { progress.update(done); });
  progress.finish();
  std::cout << "wrote " << options.cams << " cameras x " << options.frames << " frames (" << options.width << "x"
            << options.height << ") into " << out << "\n";
  return 0;
}

}  // namespace s4d::cli
