// Parsing of COLMAP's cameras / images / points3D files (see colmap_model.h), plus read_colmap_points
// for the dataset's initial point cloud.
#include "colmap_model.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>

#include "dataset_parts.h"

namespace s4d::data::colmap {
namespace {

namespace fs = std::filesystem;
using detail::fail;

// COLMAP's model table (src/colmap/sensor/models.h): ids are what cameras.bin stores, so this order
// is fixed by the format.
constexpr CameraModel kModels[] = {
    {0, "SIMPLE_PINHOLE", 3, true, false},         {1, "PINHOLE", 4, false, false},
    {2, "SIMPLE_RADIAL", 4, true, false},          {3, "RADIAL", 5, true, false},
    {4, "OPENCV", 8, false, false},                {5, "OPENCV_FISHEYE", 8, false, true},
    {6, "FULL_OPENCV", 12, false, false},          {7, "FOV", 5, false, false},
    {8, "SIMPLE_RADIAL_FISHEYE", 4, true, true},   {9, "RADIAL_FISHEYE", 5, true, true},
    {10, "THIN_PRISM_FISHEYE", 12, false, true},   {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16, false, true},
};

// ---- binary files ----

// Sequential little-endian reads (the host is little endian, as for PLY) that know how many bytes
// are left, so truncation and impossible counts are reported instead of read past or allocated.
class BinaryFile {
 public:
  explicit BinaryFile(const fs::path& path) : path_(path), in_(path, std::ios::binary | std::ios::ate) {
    if (!in_) fail(path, "cannot open");
    size_ = static_cast<uint64_t>(in_.tellg());
    in_.seekg(0);
  }

  template <typename T>
  T get(const std::string& field) {
    T v{};
    need(sizeof v, field);
    in_.read(reinterpret_cast<char*>(&v), sizeof v);
    advance(sizeof v, field);
    return v;
  }

  void skip(uint64_t bytes, const std::string& field) {
    need(bytes, field);
    in_.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
    advance(bytes, field);
  }

  std::string get_string(const std::string& field) {
    std::string s;
    for (char c; (c = get<char>(field)) != '\0';) s += c;
    return s;
  }

  // A count of records each at least `min_bytes` long, refused when the rest of the file cannot
  // hold them: a corrupt count must not turn into a huge allocation.
  uint64_t get_count(const std::string& field, uint64_t min_bytes) {
    const uint64_t n = get<uint64_t>(field);
    if (n > remaining() / min_bytes) {
      fail(path_, field + ": " + std::to_string(n) + " records need at least " + std::to_string(min_bytes) +
                      " bytes each but only " + std::to_string(remaining()) + " bytes follow (truncated or corrupt file)");
    }
    return n;
  }

  void expect_end(uint64_t records) const {
    if (remaining() != 0) {
      fail(path_, std::to_string(remaining()) + " unexpected bytes after the " + std::to_string(records) +
                      " records the header counts");
    }
  }

  uint64_t remaining() const { return size_ - pos_; }

 private:
  void need(uint64_t bytes, const std::string& field) const {
    if (remaining() < bytes) fail(path_, field + ": file truncated (ends after " + std::to_string(size_) + " bytes)");
  }
  void advance(uint64_t bytes, const std::string& field) {
    if (!in_) fail(path_, field + ": read error");
    pos_ += bytes;
  }

  fs::path path_;
  std::ifstream in_;
  uint64_t size_ = 0, pos_ = 0;
};

// Smallest possible record sizes, for BinaryFile::get_count.
constexpr uint64_t kMinCameraBytes = 4 + 4 + 8 + 8 + 3 * 8;           // the smallest model has 3 params
constexpr uint64_t kMinImageBytes = 4 + 7 * 8 + 4 + 1 + 8;            // empty name, no 2D points
constexpr uint64_t kMinPointBytes = 8 + 3 * 8 + 3 + 8 + 8;            // empty track
constexpr uint64_t kPoint2dBytes = 8 + 8 + 8, kTrackBytes = 4 + 4;

std::vector<Camera> read_cameras_bin(const fs::path& path) {
  BinaryFile f(path);
  const uint64_t n = f.get_count("camera count", kMinCameraBytes);
  std::vector<Camera> cameras(n);
  for (uint64_t i = 0; i < n; ++i) {
    Camera& c = cameras[i];
    c.id = f.get<int32_t>("camera record " + std::to_string(i) + ": camera_id");
    const std::string where = "camera " + std::to_string(c.id) + ": ";
    const int32_t model_id = f.get<int32_t>(where + "model_id");
    c.model = camera_model(model_id);
    if (!c.model) fail(path, where + "model_id " + std::to_string(model_id) + " is not a COLMAP camera model");
    c.width = f.get<uint64_t>(where + "width");
    c.height = f.get<uint64_t>(where + "height");
    for (int k = 0; k < c.model->num_params; ++k) c.params.push_back(f.get<double>(where + "params"));
  }
  f.expect_end(n);
  return cameras;
}

std::vector<Image> read_images_bin(const fs::path& path) {
  BinaryFile f(path);
  const uint64_t n = f.get_count("image count", kMinImageBytes);
  std::vector<Image> images(n);
  for (uint64_t i = 0; i < n; ++i) {
    Image& im = images[i];
    im.id = f.get<int32_t>("image record " + std::to_string(i) + ": image_id");
    const std::string where = "image " + std::to_string(im.id) + ": ";
    for (double& v : im.q) v = f.get<double>(where + "qvec");
    for (double& v : im.t) v = f.get<double>(where + "tvec");
    im.camera_id = f.get<int32_t>(where + "camera_id");
    im.name = f.get_string(where + "name");
    const uint64_t points = f.get_count(where + "num_points2D", kPoint2dBytes);
    f.skip(points * kPoint2dBytes, where + "points2D");
  }
  f.expect_end(n);
  return images;
}

std::vector<Point> read_points3d_bin(const fs::path& path) {
  BinaryFile f(path);
  const uint64_t n = f.get_count("point count", kMinPointBytes);
  std::vector<Point> points(n);
  for (uint64_t i = 0; i < n; ++i) {
    Point& p = points[i];
    const uint64_t id = f.get<uint64_t>("point record " + std::to_string(i) + ": point3D_id");
    const std::string where = "point " + std::to_string(id) + ": ";
    for (double& v : p.xyz) v = f.get<double>(where + "xyz");
    for (uint8_t& v : p.rgb) v = f.get<uint8_t>(where + "rgb");
    f.skip(8, where + "error");
    const uint64_t track = f.get_count(where + "track_length", kTrackBytes);
    f.skip(track * kTrackBytes, where + "track");
  }
  f.expect_end(n);
  return points;
}

// ---- text files ----

// Lines of a COLMAP text file, split on whitespace, with their numbers for messages.
class TextFile {
 public:
  explicit TextFile(const fs::path& path) : path_(path), in_(path) {
    if (!in_) fail(path, "cannot open");
  }

  // The next line that is neither blank nor a '#' comment; false at the end of the file.
  bool next_record(std::vector<std::string>& tokens) {
    while (next_line(tokens)) {
      if (!tokens.empty() && tokens[0][0] != '#') return true;
    }
    return false;
  }

  // The next line, whatever it holds; false at the end of the file.
  bool next_line(std::vector<std::string>& tokens) {
    std::string line;
    if (!std::getline(in_, line)) return false;
    ++line_;
    tokens.clear();
    size_t at = 0;
    while (true) {
      at = line.find_first_not_of(" \t\r", at);
      if (at == std::string::npos) break;
      const size_t end = line.find_first_of(" \t\r", at);
      tokens.push_back(line.substr(at, end - at));
      at = end;
    }
    return true;
  }

  std::string where() const { return "line " + std::to_string(line_) + ": "; }

  [[noreturn]] void error(const std::string& what) const { fail(path_, where() + what); }

  double number(const std::string& token, const std::string& field) const {
    const char* s = token.c_str();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE) error(field + ": '" + token + "' is not a number");
    return v;
  }

  long long integer(const std::string& token, const std::string& field, long long lo, long long hi) const {
    const char* s = token.c_str();
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE) error(field + ": '" + token + "' is not an integer");
    if (v < lo || v > hi) error(field + ": " + token + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }

  int int32(const std::string& token, const std::string& field) const {
    return static_cast<int>(integer(token, field, std::numeric_limits<int32_t>::min(), std::numeric_limits<int32_t>::max()));
  }

 private:
  fs::path path_;
  std::ifstream in_;
  size_t line_ = 0;
};

std::vector<Camera> read_cameras_txt(const fs::path& path) {
  TextFile f(path);
  std::vector<Camera> cameras;
  std::vector<std::string> t;
  while (f.next_record(t)) {
    if (t.size() < 4) f.error("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[], got " + std::to_string(t.size()) + " fields");
    Camera c;
    c.id = f.int32(t[0], "camera_id");
    const std::string where = "camera " + std::to_string(c.id) + ": ";
    c.model = camera_model(t[1]);
    if (!c.model) f.error(where + "model '" + t[1] + "' is not a COLMAP camera model");
    c.width = static_cast<uint64_t>(f.integer(t[2], where + "width", 0, std::numeric_limits<long long>::max()));
    c.height = static_cast<uint64_t>(f.integer(t[3], where + "height", 0, std::numeric_limits<long long>::max()));
    if (t.size() != 4 + static_cast<size_t>(c.model->num_params)) {
      f.error(where + "params: " + c.model->name + " has " + std::to_string(c.model->num_params) + ", got " +
              std::to_string(t.size() - 4));
    }
    for (size_t k = 4; k < t.size(); ++k) c.params.push_back(f.number(t[k], where + "params"));
    cameras.push_back(std::move(c));
  }
  return cameras;
}

std::vector<Image> read_images_txt(const fs::path& path) {
  TextFile f(path);
  std::vector<Image> images;
  std::vector<std::string> t;
  while (f.next_record(t)) {
    if (t.size() != 10) {
      f.error("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME (names without spaces), got " +
              std::to_string(t.size()) + " fields");
    }
    Image im;
    im.id = f.int32(t[0], "image_id");
    const std::string where = "image " + std::to_string(im.id) + ": ";
    for (size_t k = 0; k < 4; ++k) im.q[k] = f.number(t[1 + k], where + "qvec");
    for (size_t k = 0; k < 3; ++k) im.t[k] = f.number(t[5 + k], where + "tvec");
    im.camera_id = f.int32(t[8], where + "camera_id");
    im.name = t[9];
    // The second line of each image is its 2D points (possibly empty). Checking its shape catches a
    // file with one line per image, which would otherwise silently swallow every second image.
    if (f.next_line(t)) {
      if (t.size() % 3 != 0) f.error(where + "points2D: expected X Y POINT3D_ID triples, got " + std::to_string(t.size()) + " fields");
      for (const std::string& token : t) f.number(token, where + "points2D");
    }
    images.push_back(std::move(im));
  }
  return images;
}

std::vector<Point> read_points3d_txt(const fs::path& path) {
  TextFile f(path);
  std::vector<Point> points;
  std::vector<std::string> t;
  while (f.next_record(t)) {
    if (t.size() < 8 || t.size() % 2 != 0) {
      f.error("expected POINT3D_ID X Y Z R G B ERROR then (IMAGE_ID POINT2D_IDX) pairs, got " + std::to_string(t.size()) + " fields");
    }
    Point p;
    f.integer(t[0], "point3D_id", 0, std::numeric_limits<long long>::max());
    const std::string where = "point " + t[0] + ": ";
    for (size_t k = 0; k < 3; ++k) p.xyz[k] = f.number(t[1 + k], where + "xyz");
    for (size_t k = 0; k < 3; ++k) p.rgb[k] = static_cast<uint8_t>(f.integer(t[4 + k], where + "rgb", 0, 255));
    points.push_back(p);
  }
  return points;
}

// Picks the parser by extension.
template <typename T>
std::vector<T> read_by_extension(const fs::path& path, std::vector<T> (*bin)(const fs::path&),
                                 std::vector<T> (*txt)(const fs::path&)) {
  if (!fs::is_regular_file(path)) fail(path, "missing");
  if (path.extension() == ".bin") return bin(path);
  if (path.extension() == ".txt") return txt(path);
  fail(path, "expected a .bin or .txt COLMAP file");
}

}  // namespace

const CameraModel* camera_model(int id) {
  for (const CameraModel& m : kModels) {
    if (m.id == id) return &m;
  }
  return nullptr;
}

const CameraModel* camera_model(const std::string& name) {
  for (const CameraModel& m : kModels) {
    if (name == m.name) return &m;
  }
  return nullptr;
}

std::vector<Camera> read_cameras(const fs::path& path) { return read_by_extension(path, read_cameras_bin, read_cameras_txt); }
std::vector<Image> read_images(const fs::path& path) { return read_by_extension(path, read_images_bin, read_images_txt); }
std::vector<Point> read_points3d(const fs::path& path) {
  return read_by_extension(path, read_points3d_bin, read_points3d_txt);
}

}  // namespace s4d::data::colmap

namespace s4d::data::detail {

void read_colmap_points(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors) {
  const std::vector<colmap::Point> parsed = colmap::read_points3d(path);
  points.clear();
  colors.clear();
  points.reserve(3 * parsed.size());
  colors.reserve(3 * parsed.size());
  for (size_t i = 0; i < parsed.size(); ++i) {
    for (size_t k = 0; k < 3; ++k) {
      if (!std::isfinite(parsed[i].xyz[k])) fail(path, "point record " + std::to_string(i) + ": xyz: non-finite value");
      points.push_back(static_cast<float>(parsed[i].xyz[k]));
      colors.push_back(static_cast<float>(parsed[i].rgb[k]) / 255.0f);
    }
  }
}

}  // namespace s4d::data::detail
