#include "s4d/synth/dataset.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "s4d/data/npy.h"
#include "s4d/data/video_writer.h"
#include "s4d/io/image_io.h"
#include "s4d/synth/bodies.h"
#include "s4d/synth/camera_rig.h"
#include "s4d/synth/dnerf_layout.h"
#include "s4d/synth/point_cloud.h"
#include "s4d/synth/render.h"
#include "s4d/synth/scene.h"
#include "s4d/synth/scene_json.h"
#include "s4d/util/atomic_file.h"

namespace s4d::synth {
namespace {

namespace fs = std::filesystem;

// The fixed-width names (camNN, NNNN) keep lexicographic and numeric order the same, which
// loaders that sort directory listings rely on.
constexpr int kMaxCams = 99, kMaxFrames = 9999, kMinSide = 8, kMaxSide = 4096;

// DyNeRF's capture rate; the loader ignores it (time comes from the frame index).
constexpr double kVideoFps = 30;
// synth --glossy: the highlight's strength, about half the brightest albedo, so that views differ clearly.
constexpr double kGlossySpecular = 0.5;

// Margin on the rendered depth range, so content at the edges of the range is not clipped.
constexpr double kNearScale = 0.9, kFarScale = 1.1;

void check_range(const char* what, int value, int lo, int hi) {
  if (value < lo || value > hi)
    throw std::invalid_argument(std::string(what) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                "], got " + std::to_string(value));
}

// Marks a DIR.partial as ours, so that a later run may delete it without risking user files.
constexpr char kPartialMarker[] = ".style4d-synth-partial";

// A dataset is never written over: `out` must not exist or be an empty directory.
void check_destination(const fs::path& out) {
  if (!fs::exists(out)) return;
  if (!fs::is_directory(out) || !fs::is_empty(out))
    throw std::invalid_argument(out.string() + " already exists and is not an empty directory; choose a new --out");
}

// Only now does DIR appear, complete. An empty directory the user made is replaced.
void finish(const fs::path& partial, const fs::path& out) {
  fs::remove(partial / kPartialMarker);
  if (fs::exists(out)) fs::remove(out);
  fs::rename(partial, out);
}

// Cameras in turn at 1, 1.4 and 0.75 times the rig's distance, with 1, 1.2 and 0.85 times its
// focal length, so the objects cover different numbers of pixels from view to view; the test
// camera (first) keeps the rig's.
void vary_distances(std::vector<PinholeCamera>& cameras, Vec3 centre) {
  constexpr double kDistance[3] = {1.0, 1.4, 0.75}, kFocal[3] = {1.0, 1.2, 0.85};
  for (size_t k = 0; k < cameras.size(); ++k) {
    cameras[k].position = centre + (cameras[k].position - centre) * kDistance[k % 3];
    cameras[k].focal *= kFocal[k % 3];
  }
}

}  // namespace

void check_options(const SynthOptions& o) {
  check_range("--cams", o.cams, 2, kMaxCams);
  check_range("--frame-count", o.frames, 2, kMaxFrames);
  check_range("--size width", o.width, kMinSide, kMaxSide);
  check_range("--size height", o.height, kMinSide, kMaxSide);
  check_range("samples per axis", o.samples_per_axis, 1, 16);
  check_range("point count", o.points, 1, 10'000'000);
  if (o.rgba && !o.dnerf) throw std::invalid_argument("--rgba needs --dnerf (the DyNeRF layout's frames are RGB)");
  check_range("--random-init", o.random_init, 0, 10'000'000);
  if (!o.motion.empty()) motion_bodies(o.motion);  // names the choices when unknown
  if (o.video && o.dnerf) throw std::invalid_argument("--video writes the DyNeRF layout; the D-NeRF layout has image files only");
  if (o.dnerf && o.cams < 3) throw std::invalid_argument("the D-NeRF layout needs --cams >= 3 (one test camera, two or more training cameras)");
  if (o.video && (o.width % 2 != 0 || o.height % 2 != 0))
    throw std::invalid_argument("--size must be even on both sides with --video (mp4v stores chroma at half "
                                "resolution), got " + std::to_string(o.width) + "x" + std::to_string(o.height));
}

std::string camera_dir_name(int cam) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "cam%02d", cam);
  return buf;
}

std::string frame_file_name(int frame) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04d.png", frame);
  return buf;
}

void write_dataset(const fs::path& out_arg, const SynthOptions& options, const ProgressFn& progress) {
  check_options(options);
  // "DIR/" must give DIR.partial beside DIR, not DIR/.partial inside it.
  fs::path out = out_arg.lexically_normal();
  if (!out.has_filename()) out = out.parent_path();
  if (out.empty()) throw std::invalid_argument("--out must name a directory");
  check_destination(out);
  fs::path partial = out;
  partial += ".partial";
  if (fs::exists(partial)) {
    // What an interrupted earlier run left behind is ours to delete; anything else is not.
    if (!fs::exists(partial / kPartialMarker))
      throw std::invalid_argument(partial.string() + " exists and was not made by style4d synth; move it away");
    fs::remove_all(partial);
  }
  fs::create_directories(partial);
  util::write_file_atomic(partial / kPartialMarker, "an unfinished style4d synth dataset; safe to delete\n");

  Scene scene;
  if (options.glossy) scene.specular = kGlossySpecular;
  ArcRig rig;
  if (!options.motion.empty()) {
    scene.builtin_objects = false;
    scene.bodies = motion_bodies(options.motion);
  }
  if (options.object || !options.motion.empty()) {
    scene.room = false;
    scene.sky = {0, 0, 0};
    rig.span_deg = 360.0 * (options.cams - 1) / options.cams;
    rig.height = 2.0;  // about 27 degrees above the objects
  }
  // Neu3D holds out its centre camera as cam00: the middle camera of the arc comes first, the
  // others follow from left to right, so the test view is interpolated, not extrapolated.
  std::vector<PinholeCamera> cameras = arc_cameras(rig, scene.centre, options.cams, options.width, options.height);
  std::rotate(cameras.begin(), cameras.begin() + options.cams / 2, cameras.begin() + options.cams / 2 + 1);
  if (options.mixed_distances) vary_distances(cameras, scene.centre);
  const RenderSettings settings{options.samples_per_axis, options.seed, 0};

  const std::vector<ColouredPoint> points = options.random_init > 0
                                                ? random_points(options.random_init, options.seed)
                                                : sample_points(scene, cameras, options.points, options.seed);
  util::write_file_atomic(partial / (options.random_init > 0 ? "fused.ply" : "points3D.ply"), points_to_ply(points));
  if (options.dnerf) {
    write_dnerf_views(partial, scene, cameras, options, settings, progress);
    util::write_file_atomic(partial / "scene.json", scene_json(scene, rig, options, cameras, {}, points.size()));
    finish(partial, out);
    return;
  }

  const uint64_t total = static_cast<uint64_t>(options.cams) * static_cast<uint64_t>(options.frames);
  uint64_t done = 0;
  std::vector<DepthBounds> bounds;
  for (int c = 0; c < options.cams; ++c) {
    const fs::path cam_dir = partial / camera_dir_name(c);
    std::optional<data::VideoWriter> video;
    if (options.video) {
      video.emplace(fs::path(cam_dir) += ".mp4", options.width, options.height, kVideoFps);
    } else {
      fs::create_directories(cam_dir);
    }
    double lo = 1e300, hi = -1e300;
    for (int f = 0; f < options.frames; ++f) {
      const double t = options.still ? 0.0 : static_cast<double>(f) / (options.frames - 1);
      RenderedView view = render_view(scene, cameras[static_cast<size_t>(c)], t, settings);
      lo = std::min(lo, view.min_depth);
      hi = std::max(hi, view.max_depth);
      const io::ImageF image{view.width, view.height, 3, std::move(view.rgb)};
      if (video) {
        video->write(image);
      } else {
        io::write_png(cam_dir / frame_file_name(f), image);
      }
      if (progress) progress(++done, total);
    }
    if (!(lo > 0 && lo <= hi)) throw std::runtime_error(camera_dir_name(c) + " sees no surface in front of it");
    bounds.push_back({lo * kNearScale, hi * kFarScale});
  }

  data::NpyArray poses{{static_cast<size_t>(options.cams), 17}, {}};
  for (size_t c = 0; c < cameras.size(); ++c) {
    const std::array<double, 15> m = llff_pose(cameras[c]);
    poses.values.insert(poses.values.end(), m.begin(), m.end());
    poses.values.push_back(bounds[c].near);
    poses.values.push_back(bounds[c].far);
  }
  data::write_npy(partial / "poses_bounds.npy", poses);
  util::write_file_atomic(partial / "scene.json", scene_json(scene, rig, options, cameras, bounds, points.size()));
  finish(partial, out);
}

}  // namespace s4d::synth
