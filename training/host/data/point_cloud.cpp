// Initial point clouds: PLY (COLMAP / Open3D / 4DGaussians output, or what a scene generator writes),
// [P, 3] NumPy arrays (HyperNeRF's points.npy), and COLMAP's points3D.bin / .txt (colmap_model.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>

#include "dataset_parts.h"
#include "s4d/data/npy.h"
#include "s4d/io/ply_header.h"

namespace s4d::data::detail {
namespace {

constexpr float kGrey = 0.5f;  // colour of points whose file has none

struct Field {
  size_t offset = 0;  // bytes into a binary item
  int index = 0;      // token index in an ASCII line
  io::PlyScalar type = io::PlyScalar::float32;
};

// Where property `name` of `vertex` sits, when it exists with one of `types`; nullopt when it is absent.
std::optional<Field> find_field(const std::filesystem::path& path, const io::PlyElement& vertex, const char* name,
                                std::initializer_list<io::PlyScalar> types) {
  Field f;
  for (const io::PlyProperty& p : vertex.properties) {
    if (p.name == name) {
      if (std::find(types.begin(), types.end(), p.type) == types.end()) {
        std::string allowed;
        for (io::PlyScalar t : types) allowed += std::string(allowed.empty() ? "" : " or ") + io::ply_scalar_name(t);
        fail(path, std::string("vertex property '") + name + "' must be " + allowed + ", is " + io::ply_scalar_name(p.type));
      }
      f.type = p.type;
      return f;
    }
    f.offset += io::ply_scalar_size(p.type);
    ++f.index;
  }
  return std::nullopt;
}

Field required_field(const std::filesystem::path& path, const io::PlyElement& vertex, const char* name,
                     std::initializer_list<io::PlyScalar> types) {
  const std::optional<Field> f = find_field(path, vertex, name, types);
  if (!f) fail(path, std::string("vertex has no property '") + name + "'");
  return *f;
}

float read_coordinate(const std::string& item, const Field& f) {
  if (f.type == io::PlyScalar::float64) {
    double d;
    std::memcpy(&d, item.data() + f.offset, sizeof d);
    return static_cast<float>(d);
  }
  float v;
  std::memcpy(&v, item.data() + f.offset, sizeof v);
  return v;
}

// HyperNeRF's points.npy: [P, 3] world positions (float32 or float64).
void read_npy_points(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors) {
  const NpyArray a = read_npy(path);
  if (a.shape.size() != 2 || a.shape[1] != 3) fail(path, "shape must be (P, 3) positions");
  points.assign(a.values.begin(), a.values.end());
  colors.assign(points.size(), kGrey);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i])) fail(path, "row " + std::to_string(i / 3) + ": non-finite position");
  }
}

}  // namespace

void read_points(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors) {
  const std::string name = path.filename().string();
  if (path.extension() == ".ply") return read_point_cloud(path, points, colors);
  if (path.extension() == ".npy") return read_npy_points(path, points, colors);
  if (name == "points3D.bin" || name == "points3D.txt") return read_colmap_points(path, points, colors);
  fail(path, "unknown point cloud format (expected .ply, .npy, points3D.bin or points3D.txt)");
}

void read_point_cloud(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors) {
  const io::PlyHeader header = io::read_ply_header(path);
  // Only the first element can be located without parsing those before it, and the vertices come
  // first in every writer we know of.
  if (header.elements.empty() || header.elements[0].name != "vertex") fail(path, "first element must be 'vertex'");
  const io::PlyElement& vertex = header.elements[0];
  if (vertex.has_list()) fail(path, "vertex has a list property");
  const bool ascii = header.format == "ascii";
  if (!ascii && header.format != "binary_little_endian") fail(path, "unsupported format '" + header.format + "'");

  using io::PlyScalar;
  const Field xyz[3] = {required_field(path, vertex, "x", {PlyScalar::float32, PlyScalar::float64}),
                        required_field(path, vertex, "y", {PlyScalar::float32, PlyScalar::float64}),
                        required_field(path, vertex, "z", {PlyScalar::float32, PlyScalar::float64})};
  // Colours are optional (grey without them), but all three or none.
  const std::optional<Field> rgb_found[3] = {find_field(path, vertex, "red", {PlyScalar::uint8}),
                                             find_field(path, vertex, "green", {PlyScalar::uint8}),
                                             find_field(path, vertex, "blue", {PlyScalar::uint8})};
  const bool has_rgb = rgb_found[0] && rgb_found[1] && rgb_found[2];
  if (!has_rgb && (rgb_found[0] || rgb_found[1] || rgb_found[2])) fail(path, "vertex has some of red, green, blue but not all");

  const size_t count = static_cast<size_t>(vertex.count);
  const size_t item_size = vertex.fixed_item_size();
  // Checked before allocating, so a corrupt count cannot ask for terabytes. An ASCII vertex takes at
  // least one digit and one separator per value.
  const uintmax_t data_bytes = std::filesystem::file_size(path) - header.data_offset;
  const size_t min_item_bytes = ascii ? 2 * vertex.properties.size() : item_size;
  if (count > data_bytes / min_item_bytes) {
    fail(path, "truncated: " + std::to_string(count) + " vertices declared, at most " +
                   std::to_string(data_bytes / min_item_bytes) + " present");
  }
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  points.assign(3 * count, 0.0f);
  colors.assign(3 * count, kGrey);
  std::string item(item_size, '\0');
  for (size_t i = 0; i < count; ++i) {
    if (ascii) {
      std::string line;
      std::vector<std::string> tokens;
      if (std::getline(in, line)) {
        std::istringstream words(line);
        for (std::string w; words >> w;) tokens.push_back(w);
      }
      if (tokens.size() != vertex.properties.size()) fail(path, "vertex " + std::to_string(i) + ": wrong value count");
      try {
        for (size_t k = 0; k < 3; ++k) {
          points[3 * i + k] = std::stof(tokens[static_cast<size_t>(xyz[k].index)]);
          if (!has_rgb) continue;
          const int level = std::stoi(tokens[static_cast<size_t>(rgb_found[k]->index)]);
          if (level < 0 || level > 255) throw std::out_of_range("uchar");
          colors[3 * i + k] = static_cast<float>(level) / 255.0f;
        }
      } catch (const std::exception&) {
        fail(path, "vertex " + std::to_string(i) + ": malformed or out-of-range number");
      }
    } else {
      if (!in.read(item.data(), static_cast<std::streamsize>(item_size))) {
        fail(path, "truncated: " + std::to_string(count) + " vertices declared, " + std::to_string(i) + " present");
      }
      for (size_t k = 0; k < 3; ++k) {
        points[3 * i + k] = read_coordinate(item, xyz[k]);
        if (has_rgb) colors[3 * i + k] = static_cast<float>(static_cast<unsigned char>(item[rgb_found[k]->offset])) / 255.0f;
      }
    }
  }
  for (size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i])) fail(path, "vertex " + std::to_string(i / 3) + ": non-finite position");
  }
}

}  // namespace s4d::data::detail
