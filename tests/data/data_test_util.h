// Builders of tiny datasets on disk for the loader tests, written straight from the layout
// descriptions (LLFF 3x5 poses, transforms JSON by hand) rather than through the loaders' helpers.
#pragma once
#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "../io/io_test_util.h"
#include "s4d/data/dataset.h"
#include "s4d/data/npy.h"
#include "s4d/data/video_writer.h"
#include "s4d/io/image_io.h"
#include "s4d/util/vec3.h"

namespace s4d::test {

// Pixel (u, v) and depth of world point p in a view, through world_to_cam and the intrinsics.
inline Vec3 project(const io::CameraView& c, const Vec3& p) {
  Vec3 x{};
  for (size_t i = 0; i < 3; ++i) {
    x[i] = c.world_to_cam[i * 4] * p[0] + c.world_to_cam[i * 4 + 1] * p[1] + c.world_to_cam[i * 4 + 2] * p[2] +
           c.world_to_cam[i * 4 + 3];
  }
  return {c.fx * x[0] / x[2] + c.cx, c.fy * x[1] / x[2] + c.cy, x[2]};
}

// Camera centre -R^T t.
inline Vec3 centre(const io::CameraView& c) {
  const auto& m = c.world_to_cam;
  Vec3 o{};
  for (size_t i = 0; i < 3; ++i) o[i] = -(m[i] * m[3] + m[4 + i] * m[7] + m[8 + i] * m[11]);
  return o;
}

// A deterministic 8-bit-exact colour: value (level / 255) of channel k at (x, y) in frame `seed`.
inline float level(int x, int y, int k, int seed) {
  return static_cast<float>((x * 7 + y * 13 + k * 29 + seed * 31) % 256) / 255.0f;
}

inline io::ImageF pattern(int width, int height, int channels, int seed) {
  io::ImageF im{width, height, channels, {}};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int k = 0; k < channels; ++k) im.data.push_back(level(x, y, k, seed));
    }
  }
  return im;
}

// A colour that varies slowly over the image, frame `seed` (value of channel k at (x, y)): lossy video
// codecs keep such content within a few levels, where `level`'s fine pattern would be smeared.
inline float smooth_level(int x, int y, int k, int seed) {
  return 0.5f + 0.35f * static_cast<float>(std::sin(0.12 * x + 0.08 * y + 0.3 * k + 0.2 * seed));
}

inline io::ImageF smooth_pattern(int width, int height, int seed) {
  io::ImageF im{width, height, 3, {}};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int k = 0; k < 3; ++k) im.data.push_back(smooth_level(x, y, k, seed));
    }
  }
  return im;
}

// One LLFF poses_bounds row: rotation columns (down, right, back), centre, (H, W, focal), near, far.
struct LlffCamera {
  Vec3 down, right, back, centre;
  double height, width, focal;
};

inline void write_poses_bounds(const std::filesystem::path& path, const std::vector<LlffCamera>& cams) {
  data::NpyArray a{{cams.size(), 17}, {}};
  for (const LlffCamera& c : cams) {
    const double hwf[3] = {c.height, c.width, c.focal};
    for (size_t r = 0; r < 3; ++r) {
      for (double v : {c.down[r], c.right[r], c.back[r], c.centre[r], hwf[r]}) a.values.push_back(v);
    }
    a.values.push_back(0.1);
    a.values.push_back(100.0);
  }
  data::write_npy(path, a);
}

// A camera at `centre` looking at the origin with world +y up, as LLFF columns.
inline LlffCamera look_at_origin(const Vec3& c, double height, double width, double focal) {
  auto normalise = [](Vec3 v) {
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return Vec3{v[0] / n, v[1] / n, v[2] / n};
  };
  auto cross = [](const Vec3& a, const Vec3& b) {
    return Vec3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const Vec3 back = normalise(c);  // from the origin towards the camera
  const Vec3 right = normalise(cross({0, 1, 0}, back));
  const Vec3 up = cross(back, right);
  return {{-up[0], -up[1], -up[2]}, right, back, c, height, width, focal};
}

// The standard test scene: 3 cameras x 4 frames of 16x12 RGB. cam00 sits on +z at distance 5 with
// the identity OpenGL orientation (right +x, up +y, looking down -z), focal 10.
inline std::vector<LlffCamera> dynerf_cameras() {
  return {{{0, -1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 5}, 12, 16, 10},
          look_at_origin({4, 1, 3}, 12, 16, 10),
          look_at_origin({-3, 2, 4}, 12, 16, 10)};
}

inline void write_dynerf(const std::filesystem::path& root, const std::vector<LlffCamera>& cams, int frames = 4) {
  std::filesystem::create_directories(root);
  write_poses_bounds(root / "poses_bounds.npy", cams);
  for (size_t c = 0; c < cams.size(); ++c) {
    const auto dir = root / ("cam0" + std::to_string(c));
    std::filesystem::create_directories(dir);
    for (int f = 0; f < frames; ++f) {
      const std::string name = std::string(f < 10 ? "000" : "00") + std::to_string(f) + ".png";
      io::write_png(dir / name, pattern(16, 12, 3, static_cast<int>(c) * 10 + f));
    }
  }
}

// The standard scene with camera c as camNN.mp4 (mp4v) of `frames[c]` frames (default 4 for each)
// showing smooth_pattern(16, 12, 10 c + f), instead of frame folders.
inline void write_dynerf_videos(const std::filesystem::path& root, const std::vector<LlffCamera>& cams,
                                std::vector<int> frames = {}) {
  frames.resize(cams.size(), 4);
  std::filesystem::create_directories(root);
  write_poses_bounds(root / "poses_bounds.npy", cams);
  for (size_t c = 0; c < cams.size(); ++c) {
    data::VideoWriter video(root / ("cam0" + std::to_string(c) + ".mp4"), 16, 12);
    for (int f = 0; f < frames[c]; ++f) video.write(smooth_pattern(16, 12, static_cast<int>(c) * 10 + f));
  }
}

}  // namespace s4d::test
