// The header of a PLY file (http://paulbourke.net/dataformats/ply/): format, elements and their
// properties, in file order. Used by the 3DGS reader and to list what a file holds.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace s4d::io {

enum class PlyScalar { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

// Size in bytes of one value of this type.
size_t ply_scalar_size(PlyScalar t);
// The canonical short name ("float", "uchar", ...).
const char* ply_scalar_name(PlyScalar t);

struct PlyProperty {
  std::string name;
  PlyScalar type = PlyScalar::float32;  // the item type for a list property
  bool is_list = false;
  PlyScalar list_count_type = PlyScalar::uint8;  // meaningful only when is_list
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;  // in file order

  // Bytes per item; only for elements without list properties.
  size_t fixed_item_size() const;
  bool has_list() const;
  // Index into properties, or -1.
  int find(const std::string& property_name) const;
};

struct PlyHeader {
  std::string format;                 // "binary_little_endian", "binary_big_endian" or "ascii"
  std::string version;                // "1.0"
  std::vector<std::string> comments;  // "comment" and "obj_info" lines, without the keyword
  std::vector<PlyElement> elements;   // in file order
  uint64_t data_offset = 0;           // byte offset of the first data byte after "end_header"

  // Index into elements, or -1.
  int find(const std::string& element_name) const;
};

// Parses the header only. Throws std::runtime_error naming the file and the offending line for
// a missing 'ply' magic, unknown keywords or types, malformed lines or a header without
// 'end_header'. Any format is accepted here; readers of the data check it.
PlyHeader read_ply_header(const std::filesystem::path& path);

// Human-readable listing of a header (one line per element and per property), for tools.
std::string describe_ply_header(const PlyHeader& header);

}  // namespace s4d::io
