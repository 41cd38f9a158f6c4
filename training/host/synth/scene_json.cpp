#include "s4d/synth/scene_json.h"

#include <nlohmann/json.hpp>

namespace s4d::synth {
namespace {

// ordered_json keeps the keys in the order written here, which reads better than sorted.

nlohmann::ordered_json vec(Vec3 v) { return nlohmann::ordered_json::array({v[0], v[1], v[2]}); }

nlohmann::ordered_json describe_scene(const Scene& s) {
  const WaveSheet& w = s.sheet;
  return {
      {"units", "metres; y up; time t in [0, 1]"},
      {"centre", vec(s.centre)},
      {"wall", {{"plane_z", s.wall_z}, {"x", {-s.half_width, s.half_width}}, {"y", {s.floor_y, s.wall_top}},
                {"texture", "checker with two octaves of value noise"}, {"motion", "static"}}},
      {"floor", {{"plane_y", s.floor_y}, {"x", {-s.half_width, s.half_width}}, {"z", {s.wall_z, s.floor_front}},
                 {"texture", "stripes along x crossed by a checker, value noise"}, {"motion", "static"}}},
      {"sphere", {{"centre", vec(s.sphere_centre)}, {"radius", s.sphere_radius},
                  {"texture", "hue by longitude with a latitude checker, in the sphere's frame"},
                  {"motion", "rotation about +y by sphere_turn * t radians"}, {"sphere_turn", s.sphere_turn}}},
      {"box", {{"half_extents", vec(s.box_half)}, {"arc_centre", vec(s.box_arc_centre)},
               {"arc_radius", s.box_arc_radius}, {"arc_angles", {s.box_arc_start, s.box_arc_end}},
               {"texture", "one colour per face, diagonal stripes, white border"},
               {"motion", "centre = arc_centre + arc_radius * (sin a, 0, cos a), a from arc_angles[0] to "
                          "arc_angles[1] linearly in t; the box turns about +y by a"}}},
      {"sheet", {{"x", {w.x0, w.x1}}, {"y", {w.y0, w.y1}}, {"z0", w.z0}, {"amplitude", w.amplitude},
                 {"wavelength", w.wavelength},
                 {"texture", "three colour bands along x, stripes along y"},
                 {"motion", "non-rigid: z = z0 + amplitude * (x - x0) / (x1 - x0) * "
                            "sin(2 pi ((x - x0) / wavelength - t))"}}},
      {"shading", {{"model", "Lambertian, one directional light plus ambient, no shadows"},
                   {"light_dir", vec(s.light_dir)}, {"ambient", s.ambient}}},
  };
}

}  // namespace

std::string scene_json(const Scene& scene, const ArcRig& rig, const SynthOptions& options,
                       const std::vector<PinholeCamera>& cameras, const std::vector<DepthBounds>& bounds,
                       size_t num_points) {
  nlohmann::ordered_json cams = nlohmann::ordered_json::array();
  for (size_t c = 0; c < cameras.size(); ++c)
  {
    nlohmann::ordered_json cam = {{"name", camera_dir_name(static_cast<int>(c))},
                                  {"position", vec(cameras[c].position)},
                                  {"look_at", vec(scene.centre)}};
    if (c < bounds.size()) cam["near"] = bounds[c].near, cam["far"] = bounds[c].far;
    cams.push_back(cam);
  }
  const PinholeCamera& first = cameras.front();
  const nlohmann::ordered_json doc = {
      {"generator", "style4d synth"},
      {"layout", options.dnerf ? "D-NeRF, monocular: train/r_NNN.png one camera per time (cameras 1.., jumping), "
                                 "test/r_NNN.png camera 0 at every time, transforms_{train,test}.json, points3D.ply"
                 : options.video ? "DyNeRF/Neu3D: camNN.mp4 (mp4v, 30 fps, lossy), poses_bounds.npy, points3D.ply"
                                 : "DyNeRF/Neu3D: camNN/NNNN.png, poses_bounds.npy, points3D.ply"},
      {"parameters", {{"cams", options.cams}, {"frames", options.frames}, {"width", options.width},
                      {"height", options.height}, {"seed", options.seed},
                      {"samples_per_pixel", options.samples_per_axis * options.samples_per_axis},
                      {"points", num_points}}},
      {"time", "frame k of T has t = k / (T - 1)"},
      {"intrinsics", {{"width", first.width}, {"height", first.height}, {"focal", first.focal},
                      {"cx", 0.5 * first.width}, {"cy", 0.5 * first.height}, {"fov_x_deg", rig.fov_x_deg}}},
      {"objects_only", !scene.room},
      {"motion", options.still ? "none: every frame shows t = 0"
                 : options.motion.empty() ? "built-in sphere, box and sheet" : options.motion},
      {"frames_rgba", options.rgba},
      {"shading", options.glossy ? "Lambert plus a white Blinn-Phong highlight (view-dependent)" : "Lambert (matte)"},
      {"camera_distances", options.mixed_distances ? "1, 1.4, 0.75 x the rig's, focal 1, 1.2, 0.85 x, in turn" : "one"},
      {"init_cloud", options.random_init > 0 ? "fused.ply: uniform random points in [-1.3, 1.3]^3, random colours"
                                             : "points3D.ply: surface points the cameras see at t = 0"},
      {"rig", {{"kind", options.object ? "full ring facing the scene centre" : "horizontal arc facing the scene centre"}, {"radius", rig.radius},
               {"height", rig.height}, {"span_deg", rig.span_deg}}},
      {"convention",
       {{"world", "metres, right-handed, y up"},
        {"pixels", "pixel (i, j) covers [i, i+1] x [j, j+1], rows from the top; principal point at (W/2, H/2)"},
        {"poses_bounds", "float64 [cams, 17]; row = LLFF 3x5 matrix flattened row-major, then near, far. "
                         "3x5 columns: camera-to-world rotation columns in LLFF order (down, right, back), "
                         "camera centre, (H, W, focal in pixels). With OpenGL camera axes (right r, up u, "
                         "back b; the camera looks along -b): down = -u, right = r, back = b"},
        {"near_far", "view depth range of the surfaces each camera sees over all frames, near * 0.9, far * 1.1"}}},
      {"cameras", cams},
      {"scene", describe_scene(scene)},
  };
  return doc.dump(2) + "\n";
}

}  // namespace s4d::synth
