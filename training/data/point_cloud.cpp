// points3D.ply: the initial point cloud (COLMAP / Open3D output, or what a scene generator writes).
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "dataset_parts.h"
#include "s4d/io/ply_header.h"

namespace s4d::data::detail {
namespace {

struct Field {
  size_t offset = 0;  // bytes into a binary item
  int index = 0;      // token index in an ASCII line
};

// Where property `name` of `vertex` sits; it must exist with type `type`.
Field find_field(const std::filesystem::path& path, const io::PlyElement& vertex, const char* name, io::PlyScalar type) {
  Field f;
  for (const io::PlyProperty& p : vertex.properties) {
    if (p.name == name) {
      if (p.type != type) {
        fail(path, std::string("vertex property '") + name + "' must be " + io::ply_scalar_name(type) + ", is " +
                       io::ply_scalar_name(p.type));
      }
      return f;
    }
    f.offset += io::ply_scalar_size(p.type);
    ++f.index;
  }
  fail(path, std::string("vertex has no property '") + name + "'");
}

}  // namespace

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
  const Field xyz[3] = {find_field(path, vertex, "x", PlyScalar::float32),
                        find_field(path, vertex, "y", PlyScalar::float32),
                        find_field(path, vertex, "z", PlyScalar::float32)};
  const Field rgb[3] = {find_field(path, vertex, "red", PlyScalar::uint8),
                        find_field(path, vertex, "green", PlyScalar::uint8),
                        find_field(path, vertex, "blue", PlyScalar::uint8)};

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
  colors.assign(3 * count, 0.0f);
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
          const int level = std::stoi(tokens[static_cast<size_t>(rgb[k].index)]);
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
        std::memcpy(&points[3 * i + k], item.data() + xyz[k].offset, sizeof(float));
        colors[3 * i + k] = static_cast<float>(static_cast<unsigned char>(item[rgb[k].offset])) / 255.0f;
      }
    }
  }
  for (size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i])) fail(path, "vertex " + std::to_string(i / 3) + ": non-finite position");
  }
}

}  // namespace s4d::data::detail
