// PLY header parsing. The header is ASCII lines up to "end_header"; binary data follows directly.
// Lines may end in "\r\n" (some Windows writers); keywords are separated by any whitespace.
#include "s4d/io/ply_header.h"

#include <charconv>
#include <sstream>
#include <stdexcept>

#include "file_read.h"
#include "ply_header_read.h"

namespace s4d::io {
namespace {

// Headers of real files are a few KiB; the cap stops a binary non-PLY file that happens to start
// with "ply\n" from being read whole looking for "end_header".
constexpr size_t kMaxHeaderBytes = 1 << 20;

struct TypeName {
  const char* name;
  PlyScalar type;
};
// Both the original PLY names and the sized aliases (written by e.g. Open3D and trimesh).
constexpr TypeName kTypeNames[] = {
    {"char", PlyScalar::int8},       {"uchar", PlyScalar::uint8},    {"short", PlyScalar::int16},
    {"ushort", PlyScalar::uint16},   {"int", PlyScalar::int32},      {"uint", PlyScalar::uint32},
    {"float", PlyScalar::float32},   {"double", PlyScalar::float64}, {"int8", PlyScalar::int8},
    {"uint8", PlyScalar::uint8},     {"int16", PlyScalar::int16},    {"uint16", PlyScalar::uint16},
    {"int32", PlyScalar::int32},     {"uint32", PlyScalar::uint32},  {"float32", PlyScalar::float32},
    {"float64", PlyScalar::float64},
};

bool parse_type(const std::string& word, PlyScalar& out) {
  for (const auto& t : kTypeNames) {
    if (word == t.name) {
      out = t.type;
      return true;
    }
  }
  return false;
}

std::vector<std::string> split_words(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> words;
  std::string w;
  while (s >> w) words.push_back(w);
  return words;
}

// Reads one header line (without its terminator). Returns false at end of file.
bool read_line(std::FILE* f, std::string& line, uint64_t& consumed, const std::filesystem::path& path) {
  line.clear();
  for (;;) {
    const int c = std::fgetc(f);
    if (c == EOF) return !line.empty();
    if (++consumed > kMaxHeaderBytes) detail::fail(path, "no 'end_header' in the first 1 MiB");
    if (c == '\n') break;
    line.push_back(static_cast<char>(c));
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

}  // namespace

size_t ply_scalar_size(PlyScalar t) {
  switch (t) {
    case PlyScalar::int8:
    case PlyScalar::uint8:
      return 1;
    case PlyScalar::int16:
    case PlyScalar::uint16:
      return 2;
    case PlyScalar::int32:
    case PlyScalar::uint32:
    case PlyScalar::float32:
      return 4;
    case PlyScalar::float64:
      return 8;
  }
  throw std::logic_error("ply_scalar_size: bad PlyScalar");
}

const char* ply_scalar_name(PlyScalar t) {
  // The first entries of kTypeNames are the canonical names, one per type.
  for (const auto& n : kTypeNames) {
    if (n.type == t) return n.name;
  }
  throw std::logic_error("ply_scalar_name: bad PlyScalar");
}

size_t PlyElement::fixed_item_size() const {
  size_t size = 0;
  for (const auto& p : properties) {
    if (p.is_list) throw std::logic_error("fixed_item_size on element with a list property");
    size += ply_scalar_size(p.type);
  }
  return size;
}

bool PlyElement::has_list() const {
  for (const auto& p : properties) {
    if (p.is_list) return true;
  }
  return false;
}

int PlyElement::find(const std::string& property_name) const {
  for (size_t i = 0; i < properties.size(); ++i) {
    if (properties[i].name == property_name) return static_cast<int>(i);
  }
  return -1;
}

int PlyHeader::find(const std::string& element_name) const {
  for (size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].name == element_name) return static_cast<int>(i);
  }
  return -1;
}

namespace detail {

PlyHeader read_ply_header(std::FILE* f, const std::filesystem::path& path) {
  PlyHeader header;
  std::string line;
  uint64_t consumed = 0;
  if (!read_line(f, line, consumed, path) || line != "ply") fail(path, "not a PLY file (no 'ply' magic)");
  int line_no = 1;
  auto bad_line = [&](const std::string& why) {
    fail(path, "header line " + std::to_string(line_no) + " ('" + line + "'): " + why);
  };
  bool ended = false;
  while (read_line(f, line, consumed, path)) {
    ++line_no;
    const std::vector<std::string> w = split_words(line);
    if (w.empty()) continue;
    const std::string& key = w[0];
    if (key == "end_header") {
      ended = true;
      break;
    }
    if (key == "comment" || key == "obj_info") {
      const size_t start = line.find(key) + key.size();
      const size_t text = line.find_first_not_of(" \t", start);
      header.comments.push_back(text == std::string::npos ? "" : line.substr(text));
    } else if (key == "format") {
      if (w.size() != 3) bad_line("expected 'format <type> <version>'");
      if (!header.format.empty()) bad_line("second 'format' line");
      if (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") {
        bad_line("unknown format '" + w[1] + "'");
      }
      header.format = w[1];
      header.version = w[2];
    } else if (key == "element") {
      if (w.size() != 3) bad_line("expected 'element <name> <count>'");
      PlyElement e;
      e.name = w[1];
      const char* end = w[2].data() + w[2].size();
      const auto [ptr, ec] = std::from_chars(w[2].data(), end, e.count);
      if (ec != std::errc() || ptr != end) bad_line("count '" + w[2] + "' is not a non-negative integer");
      if (header.find(e.name) >= 0) bad_line("element '" + e.name + "' declared twice");
      header.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (header.elements.empty()) bad_line("property before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        p.is_list = true;
        if (!parse_type(w[2], p.list_count_type)) bad_line("unknown type '" + w[2] + "'");
        if (!parse_type(w[3], p.type)) bad_line("unknown type '" + w[3] + "'");
        p.name = w[4];
      } else if (w.size() == 3) {
        if (!parse_type(w[1], p.type)) bad_line("unknown type '" + w[1] + "'");
        p.name = w[2];
      } else {
        bad_line("expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      PlyElement& e = header.elements.back();
      if (e.find(p.name) >= 0) bad_line("property '" + p.name + "' declared twice in element '" + e.name + "'");
      e.properties.push_back(std::move(p));
    } else {
      bad_line("unknown keyword '" + key + "'");
    }
  }
  if (!ended) fail(path, "truncated header (no 'end_header')");
  if (header.format.empty()) fail(path, "header has no 'format' line");
  header.data_offset = consumed;
  return header;
}

}  // namespace detail

PlyHeader read_ply_header(const std::filesystem::path& path) {
  const detail::FilePtr f = detail::open_for_reading(path);
  return detail::read_ply_header(f.get(), path);
}

std::string describe_ply_header(const PlyHeader& header) {
  std::ostringstream s;
  s << "format " << header.format << " " << header.version << "\n";
  for (const auto& c : header.comments) s << "comment " << c << "\n";
  for (const auto& e : header.elements) {
    s << "element " << e.name << " " << e.count << "\n";
    for (const auto& p : e.properties) {
      s << "  " << (p.is_list ? std::string("list ") + ply_scalar_name(p.list_count_type) + " " : "")
        << ply_scalar_name(p.type) << " " << p.name << "\n";
    }
  }
  return s.str();
}

}  // namespace s4d::io
