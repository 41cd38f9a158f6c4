// transforms.json reader and writer. The file stores camera-to-world in OpenGL axes; we return
// world-to-camera in OpenCV axes, the convention of the projection kernels:
//   c2w_cv = c2w_gl * diag(1, -1, -1, 1)   (flip the camera's y and z axes)
//   w2c    = [R^T | -R^T t]                 (rigid inverse of c2w_cv = [R | t])
#include "s4d/io/nerf_cameras.h"

#include <climits>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "file_read.h"
#include "s4d/util/atomic_file.h"

namespace s4d::io {
namespace {

using nlohmann::json;

// How far the 3x3 part of a transform_matrix may be from a rotation (max |R R^T - I| and
// |det - 1|), and its last row from 0 0 0 1. Files store float32 values or decimals rounded to
// 6-8 digits (errors near 1e-7); 1e-3 accepts those and rejects any real scale or shear.
constexpr double kRigidTolerance = 1e-3;

std::string field(const std::string& where, const std::string& key) { return where.empty() ? key : where + "." + key; }

// A number found under `key` in a frame or in the top-level object.
struct Found {
  double value;
  std::string key;
  std::string field;  // as named in errors: "frames[3].fl_x" or "fl_x"
};

class CameraFileReader {
 public:
  CameraFileReader(const std::filesystem::path& path, std::optional<std::pair<int, int>> default_size)
      : path_(path), default_size_(default_size) {}

  std::vector<CameraView> read() {
    const std::string text = detail::read_whole_file(path_);
    try {
      root_ = json::parse(text);
    } catch (const json::exception& e) {
      // Drop nlohmann's "[json.exception.parse_error.101] " tag; keep the position it reports.
      const std::string what = e.what();
      const size_t tag_end = what.find("] ");
      fail("malformed JSON: " + (tag_end == std::string::npos ? what : what.substr(tag_end + 2)));
    }
    if (!root_.is_object()) fail("expected a JSON object at the top level");
    if (!root_.contains("frames")) fail("missing 'frames'");
    const json& frames = root_["frames"];
    if (!frames.is_array()) fail("'frames' is not an array");
    if (frames.empty()) fail("'frames' is empty");

    std::vector<CameraView> views;
    std::map<std::string, size_t> frame_of_name;
    for (size_t i = 0; i < frames.size(); ++i) {
      views.push_back(read_frame(frames[i], i));
      const auto [it, inserted] = frame_of_name.emplace(views.back().name, i);
      if (!inserted) {
        fail("frames[" + std::to_string(i) + "]: name '" + views.back().name + "' (from file_path '" +
             views.back().file_path + "') is already used by frames[" + std::to_string(it->second) + "]");
      }
    }
    return views;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { detail::fail(path_, what); }

  // The number under `key` in `obj`, if present. JSON has no NaN or Infinity and nlohmann rejects
  // overflowing literals, so every number that parses is finite.
  std::optional<Found> number(const json& obj, const std::string& key, const std::string& where) const {
    if (!obj.contains(key)) return std::nullopt;
    const json& v = obj[key];
    if (!v.is_number()) fail(field(where, key) + ": expected a number");
    return Found{v.get<double>(), key, field(where, key)};
  }

  // The first of `keys` present in the frame, else the first present at the top level.
  std::optional<Found> first_of(const json& frame, const std::string& where,
                                std::initializer_list<const char*> keys) const {
    for (const auto* obj : {&frame, &root_}) {
      for (const char* key : keys) {
        if (auto v = number(*obj, key, obj == &frame ? where : "")) return v;
      }
    }
    return std::nullopt;
  }

  int size(const json& frame, const std::string& where, const char* key, std::optional<int> fallback) const {
    const std::optional<Found> v = first_of(frame, where, {key});
    if (!v) {
      if (fallback) return *fallback;
      fail(where + ": no image size: give 'w' and 'h' (globally or per frame) or pass the image size");
    }
    if (v->value < 1 || v->value > INT_MAX || v->value != std::floor(v->value)) {
      fail(v->field + ": expected a positive integer, got " + json(v->value).dump());
    }
    return static_cast<int>(v->value);
  }

  // Focal length in pixels from fl_* or from a field of view over `extent` pixels.
  double focal(const Found& f, int extent) const {
    if (!f.key.starts_with("camera_angle")) {
      if (!(f.value > 0)) fail(f.field + ": focal length must be positive, got " + json(f.value).dump());
      return f.value;
    }
    if (!(f.value > 0 && f.value < std::numbers::pi)) {
      fail(f.field + ": expected an angle in (0, pi) radians, got " + json(f.value).dump());
    }
    return extent / (2.0 * std::tan(f.value / 2.0));
  }

  std::array<double, 16> matrix(const json& frame, const std::string& where) const {
    const std::string name = field(where, "transform_matrix");
    if (!frame.contains("transform_matrix")) fail(where + ": missing 'transform_matrix'");
    const json& m = frame["transform_matrix"];
    std::array<double, 16> out{};
    if (!m.is_array() || m.size() != 4) fail(name + ": expected 4x4 numbers");
    for (size_t r = 0; r < 4; ++r) {
      if (!m[r].is_array() || m[r].size() != 4) fail(name + ": expected 4x4 numbers");
      for (size_t c = 0; c < 4; ++c) {
        if (!m[r][c].is_number()) fail(name + ": expected 4x4 numbers");
        out[r * 4 + c] = m[r][c].get<double>();
      }
    }
    return out;
  }

  // Checks that c2w is rigid (within kRigidTolerance) and returns w2c in OpenCV axes.
  std::array<double, 16> world_to_cam(const std::array<double, 16>& c2w_gl, const std::string& name) const {
    const double last_row_err =
        std::max({std::abs(c2w_gl[12]), std::abs(c2w_gl[13]), std::abs(c2w_gl[14]), std::abs(c2w_gl[15] - 1.0)});
    if (last_row_err > kRigidTolerance) fail(name + ": last row is not 0 0 0 1");
    auto r = [&c2w_gl](size_t i, size_t j) { return c2w_gl[i * 4 + j]; };
    double ortho_err = 0;
    for (size_t i = 0; i < 3; ++i) {
      for (size_t j = 0; j < 3; ++j) {
        const double dot = r(i, 0) * r(j, 0) + r(i, 1) * r(j, 1) + r(i, 2) * r(j, 2);
        ortho_err = std::max(ortho_err, std::abs(dot - (i == j ? 1.0 : 0.0)));
      }
    }
    const double det = r(0, 0) * (r(1, 1) * r(2, 2) - r(1, 2) * r(2, 1)) -
                       r(0, 1) * (r(1, 0) * r(2, 2) - r(1, 2) * r(2, 0)) +
                       r(0, 2) * (r(1, 0) * r(2, 1) - r(1, 1) * r(2, 0));
    if (ortho_err > kRigidTolerance || std::abs(det - 1.0) > kRigidTolerance) {
      fail(name + ": the 3x3 part is not a rotation (max |R R^T - I| = " + json(ortho_err).dump() +
           ", det = " + json(det).dump() + "); scaled or mirrored cameras are not supported");
    }
    std::array<double, 16> w2c{};
    for (size_t i = 0; i < 3; ++i) {
      // Row i of R_cv^T is column i of R_cv = R_gl * diag(1, -1, -1).
      const double sign = i == 0 ? 1.0 : -1.0;
      double t = 0;
      for (size_t j = 0; j < 3; ++j) {
        w2c[i * 4 + j] = sign * r(j, i);
        t -= w2c[i * 4 + j] * r(j, 3);
      }
      w2c[i * 4 + 3] = t;
    }
    w2c[15] = 1.0;
    return w2c;
  }

  CameraView read_frame(const json& frame, size_t index) const {
    const std::string where = "frames[" + std::to_string(index) + "]";
    if (!frame.is_object()) fail(where + ": expected an object");
    CameraView v;
    if (!frame.contains("file_path")) fail(where + ": missing 'file_path'");
    if (!frame["file_path"].is_string()) fail(where + ".file_path: expected a string");
    v.file_path = frame["file_path"].get<std::string>();
    v.name = std::filesystem::path(v.file_path).stem().string();
    if (v.name.empty()) fail(where + ".file_path: no file name in '" + v.file_path + "'");

    v.world_to_cam = world_to_cam(matrix(frame, where), where + ".transform_matrix");

    v.width = size(frame, where, "w", default_size_ ? std::optional(default_size_->first) : std::nullopt);
    v.height = size(frame, where, "h", default_size_ ? std::optional(default_size_->second) : std::nullopt);
    const std::optional<Found> fx = first_of(frame, where, {"fl_x", "camera_angle_x"});
    if (!fx) fail(where + ": no focal length: give camera_angle_x or fl_x");
    v.fx = focal(*fx, v.width);
    const std::optional<Found> fy = first_of(frame, where, {"fl_y", "camera_angle_y"});
    v.fy = fy ? focal(*fy, v.height) : v.fx;
    const std::optional<Found> cx = first_of(frame, where, {"cx"});
    const std::optional<Found> cy = first_of(frame, where, {"cy"});
    v.cx = cx ? cx->value : v.width / 2.0;
    v.cy = cy ? cy->value : v.height / 2.0;

    if (const std::optional<Found> t = number(frame, "time", where)) {
      if (t->value < 0 || t->value > 1) fail(t->field + ": expected a time in [0, 1], got " + json(t->value).dump());
      v.time = t->value;
    }
    return v;
  }

  const std::filesystem::path& path_;
  std::optional<std::pair<int, int>> default_size_;
  json root_;
};

}  // namespace

std::vector<CameraView> read_nerf_cameras(const std::filesystem::path& transforms_json,
                                          std::optional<std::pair<int, int>> default_size) {
  if (default_size && (default_size->first < 1 || default_size->second < 1)) {
    throw std::invalid_argument("read_nerf_cameras: default_size must be positive");
  }
  return CameraFileReader(transforms_json, default_size).read();
}

void write_nerf_cameras(const std::filesystem::path& path, const std::vector<CameraView>& views) {
  json frames = json::array();
  for (const CameraView& v : views) {
    if (v.file_path.empty()) throw std::invalid_argument("write_nerf_cameras: view '" + v.name + "' has no file_path");
    // nlohmann would write NaN as null, which no reader accepts.
    bool finite = std::isfinite(v.fx) && std::isfinite(v.fy) && std::isfinite(v.cx) && std::isfinite(v.cy) &&
                  (!v.time || std::isfinite(*v.time));
    for (double x : v.world_to_cam) finite = finite && std::isfinite(x);
    if (!finite) throw std::invalid_argument("write_nerf_cameras: view '" + v.name + "' has a non-finite value");
    // c2w_cv = [R^T | -R^T t]; c2w_gl = c2w_cv * diag(1, -1, -1, 1) negates its columns 1 and 2.
    const auto& m = v.world_to_cam;
    json rows = json::array();
    for (size_t i = 0; i < 3; ++i) {
      json row = json::array();
      for (size_t j = 0; j < 3; ++j) row.push_back((j == 0 ? 1.0 : -1.0) * m[j * 4 + i]);
      row.push_back(-(m[0 * 4 + i] * m[3] + m[1 * 4 + i] * m[7] + m[2 * 4 + i] * m[11]));
      rows.push_back(row);
    }
    rows.push_back({0.0, 0.0, 0.0, 1.0});
    json frame = {{"file_path", v.file_path},
                  {"transform_matrix", rows},
                  {"fl_x", v.fx},
                  {"fl_y", v.fy},
                  {"cx", v.cx},
                  {"cy", v.cy},
                  {"w", v.width},
                  {"h", v.height}};
    if (v.time) frame["time"] = *v.time;
    frames.push_back(frame);
  }
  util::write_file_atomic(path, json{{"frames", frames}}.dump(2) + "\n");
}

}  // namespace s4d::io
