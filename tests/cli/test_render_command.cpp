// `style4d render --ply --cameras --out` end to end: a PLY written byte by byte here in the layout of
// graphdeco's save_ply (not by our writer) and a hand-written transforms.json; the rendered PNG and
// EXR put each Gaussian where the camera conventions say, and bad inputs fail with nothing written.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"

#include "cli_run.h"

namespace fs = std::filesystem;

namespace {

constexpr double kC0 = 0.28209479177387814;

struct Splat {
  float x, y, z;
  float r, g, b;  // target colour
};

// graphdeco save_ply order: x y z nx ny nz f_dc_0..2 f_rest_0..(3*(K-1)-1) opacity scale_0..2 rot_0..3.
void write_ply(const fs::path& path, const std::vector<Splat>& splats, int sh_degree, bool truncate = false,
               bool drop_rot3 = false) {
  const int rest = 3 * ((sh_degree + 1) * (sh_degree + 1) - 1);
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\nelement vertex " << splats.size() << "\n";
  for (const char* p : {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"}) header << "property float " << p << "\n";
  for (int k = 0; k < rest; ++k) header << "property float f_rest_" << k << "\n";
  for (const char* p : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2"})
    header << "property float " << p << "\n";
  if (!drop_rot3) header << "property float rot_3\n";
  header << "end_header\n";
  std::string bytes = header.str();
  auto put = [&](float v) {
    char b[4];
    std::memcpy(b, &v, 4);
    bytes.append(b, 4);
  };
  for (const Splat& s : splats) {
    for (float v : {s.x, s.y, s.z, 0.0f, 0.0f, 0.0f}) put(v);
    for (float c : {s.r, s.g, s.b}) put(static_cast<float>((c - 0.5) / kC0));
    for (int k = 0; k < rest; ++k) put(0.0f);
    put(5.0f);  // opacity logit: sigmoid(5) = 0.993, capped to 0.99 at the centre
    for (int k = 0; k < 3; ++k) put(std::log(0.15f));
    for (float q : {1.0f, 0.0f, 0.0f}) put(q);
    if (!drop_rot3) put(0.0f);
  }
  if (truncate) bytes.resize(bytes.size() - 10);
  std::ofstream(path, std::ios::binary) << bytes;
}

// Frame r_000: OpenGL camera-to-world at (0, 0, 5) looking down -z, 64x48, camera_angle_x 0.8.
// Frame r_001: the same pose with per-frame fl_x/fl_y/w/h overrides (32x24).
const char* kCameras = R"({
  "camera_angle_x": 0.8, "w": 64, "h": 48,
  "frames": [
    {"file_path": "./test/r_000", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,5],[0,0,0,1]]},
    {"file_path": "./test/r_001.png", "fl_x": 40, "fl_y": 40, "w": 32, "h": 24,
     "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,5],[0,0,0,1]]}
  ]
})";

int run(const std::string& args, const fs::path& log) { return s4d::test::run_style4d("render", args, log); }
std::string read_text(const fs::path& p) { return s4d::test::read_text(p); }
fs::path fresh_dir(const std::string& name) { return s4d::test::fresh_dir("render_" + name); }

}  // namespace

TEST_CASE("render puts each Gaussian where the camera conventions say") {
  const fs::path dir = fresh_dir("ok");
  // Red in front at (-1, 0.5, 0); blue behind at (1, -0.5, -1). In OpenCV camera axes (y down,
  // z forward) they sit at (-1, -0.5, 5) and (1, 0.5, 6).
  write_ply(dir / "scene.ply", {{-1, 0.5f, 0, 1, 0, 0}, {1, -0.5f, -1, 0, 0, 1}}, 1);
  std::ofstream(dir / "transforms.json") << kCameras;
  REQUIRE(run("--ply " + (dir / "scene.ply").string() + " --cameras " + (dir / "transforms.json").string() +
                  " --out " + (dir / "out").string(),
              dir / "log.txt") == 0);

  const double fx = 32.0 / std::tan(0.4);
  auto pixel = [](double cam_x, double cam_z, double f, double centre) { return f * cam_x / cam_z + centre; };
  const s4d::io::ImageF png = s4d::io::read_png(dir / "out" / "r_000.png");
  REQUIRE(png.width == 64);
  REQUIRE(png.height == 48);
  auto at = [&](const s4d::io::ImageF& im, double u, double v, int ch) {
    const int x = static_cast<int>(std::floor(u)), y = static_cast<int>(std::floor(v));
    return im.data[static_cast<size_t>((y * im.width + x) * im.channels + ch)];
  };
  const double ru = pixel(-1, 5, fx, 32), rv = pixel(-0.5, 5, fx, 24);
  const double bu = pixel(1, 6, fx, 32), bv = pixel(0.5, 6, fx, 24);
  CHECK(at(png, ru, rv, 0) > 0.9f);  // red centre: alpha 0.99 of pure red over black
  CHECK(at(png, ru, rv, 2) < 0.05f);
  CHECK(at(png, bu, bv, 2) > 0.9f);  // blue centre
  CHECK(at(png, bu, bv, 0) < 0.05f);
  CHECK(at(png, 64 - ru, 48 - rv, 0) < 0.05f);  // the mirrored spot is empty: the y/z flip is right
  CHECK(at(png, 2, 45, 0) == 0.0f);              // background corner

  const s4d::io::ExrImage exr = s4d::io::read_exr(dir / "out" / "r_000.exr");
  auto exr_at = [&](const char* ch, double u, double v) {
    return exr.channels.at(ch)[static_cast<size_t>(std::floor(v) * 64 + std::floor(u))];
  };
  CHECK(exr_at("A", ru, rv) > 0.95f);  // 0.99 at the exact centre; the pixel centre is up to 0.7 px off
  CHECK(exr_at("Z", ru, rv) == doctest::Approx(5.0).epsilon(1e-3));  // expected depth of one opaque splat
  CHECK(exr_at("Z", bu, bv) == doctest::Approx(6.0).epsilon(1e-3));
  CHECK(exr_at("R", ru, rv) == doctest::Approx(at(png, ru, rv, 0)).epsilon(0.01));

  // Per-frame intrinsics override the global ones.
  const s4d::io::ImageF small = s4d::io::read_png(dir / "out" / "r_001.png");
  CHECK(small.width == 32);
  CHECK(small.height == 24);
  CHECK(at(small, pixel(-1, 5, 40, 16), pixel(-0.5, 5, 40, 12), 0) > 0.8f);  // a 1.2 px sigma: measured 0.87
  CHECK(fs::exists(dir / "out" / "render.json"));
}

TEST_CASE("bad inputs fail with a message naming the problem and write nothing") {
  const fs::path dir = fresh_dir("bad");
  std::ofstream(dir / "transforms.json") << kCameras;
  const std::string cams = " --cameras " + (dir / "transforms.json").string();

  write_ply(dir / "truncated.ply", {{0, 0, 0, 1, 1, 1}}, 0, /*truncate=*/true);
  CHECK(run("--ply " + (dir / "truncated.ply").string() + cams + " --out " + (dir / "o1").string(), dir / "l1") != 0);
  CHECK(read_text(dir / "l1").find("truncated") != std::string::npos);
  CHECK(!fs::exists(dir / "o1"));

  write_ply(dir / "norot.ply", {{0, 0, 0, 1, 1, 1}}, 0, false, /*drop_rot3=*/true);
  CHECK(run("--ply " + (dir / "norot.ply").string() + cams + " --out " + (dir / "o2").string(), dir / "l2") != 0);
  CHECK(read_text(dir / "l2").find("rot_3") != std::string::npos);
  CHECK(!fs::exists(dir / "o2"));

  write_ply(dir / "ok.ply", {{0, 0, 0, 1, 1, 1}}, 0);
  std::ofstream(dir / "broken.json") << R"({"camera_angle_x": 0.8, "w": 64, "h": 48, "frames": [{"file_path": "a"}]})";
  CHECK(run("--ply " + (dir / "ok.ply").string() + " --cameras " + (dir / "broken.json").string() + " --out " +
                (dir / "o3").string(),
            dir / "l3") != 0);
  CHECK(read_text(dir / "l3").find("transform_matrix") != std::string::npos);
  CHECK(!fs::exists(dir / "o3"));

  CHECK(run("--ply " + (dir / "missing.ply").string() + cams + " --out " + (dir / "o4").string(), dir / "l4") != 0);
  CHECK(read_text(dir / "l4").find("missing.ply") != std::string::npos);
}
