// 3DGS PLY reader and writer. The reader streams the vertex data in chunks so a multi-GB scene
// is never held twice in memory; the writer builds the whole file in memory and hands it to the
// atomic replace, so a crash never leaves a half-written scene.
#include "s4d/io/ply_gaussians.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "file_read.h"
#include "ply_header_read.h"
#include "s4d/util/atomic_file.h"

namespace s4d::io {
namespace {

// Floats are copied between file bytes and memory as they are.
static_assert(std::endian::native == std::endian::little, "the PLY reader assumes a little-endian host");

// Vertices decoded per fread: large enough to amortise the call, small enough (at most ~16 MiB for
// a degree-3 record of 62 doubles) not to matter next to the cloud itself.
constexpr size_t kChunkVertices = 1 << 15;

int degree_for_rest_count(size_t rest) {
  switch (rest) {
    case 0:
      return 0;
    case 9:
      return 1;
    case 24:
      return 2;
    case 45:
      return 3;
    default:
      return -1;
  }
}

// Where one required property sits in a vertex record and where its value goes in the cloud.
struct Field {
  const std::string* name;
  size_t offset;  // bytes into the record
  bool is_double;
  std::vector<float>* dest;  // value of vertex i goes to (*dest)[i * stride + first]
  size_t first;
  size_t stride;
};

std::string describe_non_finite(double v) {
  if (std::isnan(v)) return "nan";
  return v > 0 ? "inf" : "-inf";
}

class VertexDecoder {
 public:
  VertexDecoder(const PlyElement& vertex, const std::filesystem::path& path) : vertex_(vertex), path_(path) {
    size_t offset = 0;
    for (const auto& p : vertex.properties) {
      offsets_.push_back(offset);
      offset += ply_scalar_size(p.type);
    }
    record_size_ = offset;
  }

  size_t record_size() const { return record_size_; }

  // The SH degree implied by the f_rest_* properties.
  int sh_degree() const {
    size_t rest = 0;
    for (const auto& p : vertex_.properties) {
      if (is_rest_name(p.name)) ++rest;
    }
    const int degree = degree_for_rest_count(rest);
    if (degree < 0) {
      detail::fail(path_, "element 'vertex' has " + std::to_string(rest) +
                              " f_rest_* properties; expected 0, 9, 24 or 45 (SH degree 0 to 3)");
    }
    return degree;
  }

  // Adds the property `name`, whose value for vertex i goes to (*dest)[i * stride + first].
  void require(const std::string& name, std::vector<float>* dest, size_t first, size_t stride) {
    const int idx = vertex_.find(name);
    if (idx < 0) detail::fail(path_, "missing property '" + name + "' in element 'vertex'");
    const PlyProperty& p = vertex_.properties[static_cast<size_t>(idx)];
    if (p.type != PlyScalar::float32 && p.type != PlyScalar::float64) {
      detail::fail(path_, "property '" + name + "' in element 'vertex' has type " + ply_scalar_name(p.type) +
                              "; expected float or double");
    }
    fields_.push_back({&p.name, offsets_[static_cast<size_t>(idx)], p.type == PlyScalar::float64, dest, first, stride});
  }

  // Decodes `count` records starting at vertex index `first`.
  void decode(const unsigned char* records, size_t first, size_t count) const {
    for (size_t r = 0; r < count; ++r) {
      const unsigned char* rec = records + r * record_size_;
      const size_t i = first + r;
      for (const Field& f : fields_) {
        float value = 0.0f;
        if (f.is_double) {
          double d = 0.0;
          std::memcpy(&d, rec + f.offset, sizeof(d));
          if (!std::isfinite(d)) bad_value(i, f, describe_non_finite(d));
          value = static_cast<float>(d);
          if (!std::isfinite(value)) {
            std::ostringstream s;
            s << d;
            detail::fail(path_, "vertex " + std::to_string(i) + " property '" + *f.name + "' = " + s.str() +
                                    " is outside the float range");
          }
        } else {
          std::memcpy(&value, rec + f.offset, sizeof(value));
          if (!std::isfinite(value)) bad_value(i, f, describe_non_finite(value));
        }
        (*f.dest)[i * f.stride + f.first] = value;
      }
    }
  }

 private:
  static bool is_rest_name(const std::string& name) {
    constexpr std::string_view kPrefix = "f_rest_";
    if (name.size() <= kPrefix.size() || name.compare(0, kPrefix.size(), kPrefix) != 0) return false;
    return name.find_first_not_of("0123456789", kPrefix.size()) == std::string::npos;
  }

  [[noreturn]] void bad_value(size_t i, const Field& f, const std::string& what) const {
    detail::fail(path_, "vertex " + std::to_string(i) + " property '" + *f.name + "' is not finite (" + what + ")");
  }

  const PlyElement& vertex_;
  const std::filesystem::path& path_;
  std::vector<size_t> offsets_;  // per property, bytes into the record
  size_t record_size_ = 0;
  std::vector<Field> fields_;
};

// Tracks the read position against the file size so truncation is reported before reading.
class DataCursor {
 public:
  DataCursor(std::FILE* f, const std::filesystem::path& path, uint64_t start) : f_(f), path_(path), pos_(start) {
    if (fseeko(f, 0, SEEK_END) != 0) detail::fail(path, "cannot seek");
    size_ = static_cast<uint64_t>(ftello(f));
    seek(start);
  }

  uint64_t remaining() const { return size_ - pos_; }

  void skip(uint64_t bytes, const std::string& what) {
    if (bytes > remaining()) truncated(what, bytes);
    seek(pos_ + bytes);
  }

  void read(void* dst, size_t bytes, const std::string& what) {
    if (bytes > remaining()) truncated(what, bytes);
    if (std::fread(dst, 1, bytes, f_) != bytes) detail::fail(path_, "read error in " + what);
    pos_ += bytes;
  }

  [[noreturn]] void truncated(const std::string& what, uint64_t bytes) const {
    detail::fail(path_, "truncated: " + what + " (" + std::to_string(bytes) + " bytes) but only " +
                            std::to_string(remaining()) + " bytes follow");
  }

 private:
  void seek(uint64_t pos) {
    if (fseeko(f_, static_cast<off_t>(pos), SEEK_SET) != 0) detail::fail(path_, "cannot seek");
    pos_ = pos;
  }

  std::FILE* f_;
  const std::filesystem::path& path_;
  uint64_t pos_;
  uint64_t size_ = 0;
};

uint64_t checked_mul(uint64_t a, uint64_t b, const std::filesystem::path& path) {
  if (b != 0 && a > std::numeric_limits<uint64_t>::max() / b) detail::fail(path, "element size overflows");
  return a * b;
}

uint64_t read_list_count(DataCursor& cursor, PlyScalar type, const std::string& what,
                         const std::filesystem::path& path) {
  unsigned char raw[8] = {};
  cursor.read(raw, ply_scalar_size(type), what);
  auto load = [&raw]<typename T>(T) {
    T v;
    std::memcpy(&v, raw, sizeof(v));
    return v;
  };
  int64_t count = 0;
  switch (type) {
    case PlyScalar::int8:
      count = load(int8_t{});
      break;
    case PlyScalar::uint8:
      count = load(uint8_t{});
      break;
    case PlyScalar::int16:
      count = load(int16_t{});
      break;
    case PlyScalar::uint16:
      count = load(uint16_t{});
      break;
    case PlyScalar::int32:
      count = load(int32_t{});
      break;
    case PlyScalar::uint32:
      count = load(uint32_t{});
      break;
    case PlyScalar::float32:
    case PlyScalar::float64:
      detail::fail(path, what + ": list count type must be an integer type");
  }
  if (count < 0) detail::fail(path, what + ": negative list length " + std::to_string(count));
  return static_cast<uint64_t>(count);
}

// Moves past every item of `e`, list properties included.
void skip_element(DataCursor& cursor, const PlyElement& e, const std::filesystem::path& path) {
  if (!e.has_list()) {
    cursor.skip(checked_mul(e.count, e.fixed_item_size(), path),
                "header says " + std::to_string(e.count) + " items of element '" + e.name + "'");
    return;
  }
  for (uint64_t item = 0; item < e.count; ++item) {
    for (const auto& p : e.properties) {
      const std::string what = "element '" + e.name + "' item " + std::to_string(item) + " property '" + p.name + "'";
      if (p.is_list) {
        const uint64_t n = read_list_count(cursor, p.list_count_type, what, path);
        cursor.skip(checked_mul(n, ply_scalar_size(p.type), path), what);
      } else {
        cursor.skip(ply_scalar_size(p.type), what);
      }
    }
  }
}

void check_array(const std::vector<float>& v, size_t expected, const char* name) {
  if (v.size() != expected) {
    throw std::invalid_argument("GaussianCloud: " + std::string(name) + " has " + std::to_string(v.size()) +
                                " values; expected " + std::to_string(expected));
  }
}

void check_finite(const std::vector<float>& v, size_t per_vertex, const char* name) {
  for (size_t j = 0; j < v.size(); ++j) {
    if (!std::isfinite(v[j])) {
      throw std::invalid_argument("GaussianCloud: " + std::string(name) + " of vertex " +
                                  std::to_string(j / per_vertex) + " is not finite");
    }
  }
}

}  // namespace

GaussianCloud read_ply_gaussians(const std::filesystem::path& path) {
  const detail::FilePtr file = detail::open_for_reading(path);
  const PlyHeader header = detail::read_ply_header(file.get(), path);
  if (header.format != "binary_little_endian") {
    detail::fail(path, "format " + header.format + " is not supported; 3DGS files are binary_little_endian 1.0");
  }
  if (header.version != "1.0") detail::fail(path, "PLY version " + header.version + " is not supported (expected 1.0)");
  const int vertex_index = header.find("vertex");
  if (vertex_index < 0) detail::fail(path, "no element 'vertex'");
  const PlyElement& vertex = header.elements[static_cast<size_t>(vertex_index)];
  for (const auto& p : vertex.properties) {
    if (p.is_list) detail::fail(path, "list property '" + p.name + "' in element 'vertex' is not supported");
  }

  // The header is checked completely, then the size of the data, and only then is memory sized
  // after the vertex count, so a corrupt count cannot trigger a huge allocation.
  VertexDecoder decoder(vertex, path);
  GaussianCloud cloud;
  cloud.sh_degree = decoder.sh_degree();
  const size_t n = vertex.count;
  const size_t k = cloud.sh_coeffs();
  for (size_t c = 0; c < 3; ++c) {
    decoder.require(std::string(1, "xyz"[c]), &cloud.means, c, 3);
    decoder.require("scale_" + std::to_string(c), &cloud.log_scales, c, 3);
    decoder.require("f_dc_" + std::to_string(c), &cloud.sh, c, k * 3);
  }
  for (size_t c = 0; c < 4; ++c) decoder.require("rot_" + std::to_string(c), &cloud.quats, c, 4);
  decoder.require("opacity", &cloud.opacity_logits, 0, 1);
  // Channel-major in the file: the original code transposes features_rest to [N, 3, K-1].
  for (size_t j = 0; j < 3 * (k - 1); ++j) {
    const size_t ch = j / (k - 1);
    const size_t coeff = 1 + j % (k - 1);
    decoder.require("f_rest_" + std::to_string(j), &cloud.sh, coeff * 3 + ch, k * 3);
  }

  DataCursor cursor(file.get(), path, header.data_offset);
  for (size_t e = 0; e < static_cast<size_t>(vertex_index); ++e) skip_element(cursor, header.elements[e], path);
  const size_t record = decoder.record_size();
  const uint64_t total = checked_mul(n, record, path);
  if (total > cursor.remaining()) cursor.truncated("header says " + std::to_string(n) + " vertices", total);

  cloud.means.resize(3 * n);
  cloud.log_scales.resize(3 * n);
  cloud.quats.resize(4 * n);
  cloud.opacity_logits.resize(n);
  cloud.sh.resize(n * k * 3);
  std::vector<unsigned char> chunk(std::min<size_t>(n, kChunkVertices) * record);
  for (size_t first = 0; first < n; first += kChunkVertices) {
    const size_t count = std::min(kChunkVertices, n - first);
    cursor.read(chunk.data(), count * record, "vertex data");
    decoder.decode(chunk.data(), first, count);
  }
  // Bytes after the last element mean the counts are wrong: a count that lies low would otherwise
  // drop Gaussians without a word, as one that lies high is refused as truncated.
  if (static_cast<size_t>(vertex_index) + 1 == header.elements.size() && cursor.remaining() > 0) {
    detail::fail(path, std::to_string(cursor.remaining()) + " bytes follow the " + std::to_string(n) +
                           " vertices the header declares (element 'vertex' count is wrong)");
  }
  // A zero quaternion has no rotation to normalise to; renderers would draw garbage or NaN.
  for (size_t i = 0; i < n; ++i) {
    const float* q = &cloud.quats[4 * i];
    if (q[0] == 0 && q[1] == 0 && q[2] == 0 && q[3] == 0)
      detail::fail(path, "vertex " + std::to_string(i) + " properties 'rot_0'..'rot_3' are all zero (no rotation)");
  }
  return cloud;
}

void write_ply_gaussians(const std::filesystem::path& path, const GaussianCloud& cloud) {
  if (cloud.sh_degree < 0 || cloud.sh_degree > 3) {
    throw std::invalid_argument("GaussianCloud: sh_degree " + std::to_string(cloud.sh_degree) + " is not in 0..3");
  }
  if (cloud.means.size() % 3 != 0) {
    throw std::invalid_argument("GaussianCloud: means has " + std::to_string(cloud.means.size()) +
                                " values, not a multiple of 3");
  }
  const size_t n = cloud.size();
  const size_t k = cloud.sh_coeffs();
  check_array(cloud.log_scales, 3 * n, "log_scales");
  check_array(cloud.quats, 4 * n, "quats");
  check_array(cloud.opacity_logits, n, "opacity_logits");
  check_array(cloud.sh, n * k * 3, "sh");
  check_finite(cloud.means, 3, "means");
  check_finite(cloud.log_scales, 3, "log_scales");
  check_finite(cloud.quats, 4, "quats");
  check_finite(cloud.opacity_logits, 1, "opacity_logits");
  check_finite(cloud.sh, k * 3, "sh");

  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) + "\n";
  auto property = [&header](const std::string& name) { header += "property float " + name + "\n"; };
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"}) property(name);
  for (size_t j = 0; j < 3 * (k - 1); ++j) property("f_rest_" + std::to_string(j));
  property("opacity");
  for (const char* name : {"scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"}) property(name);
  header += "end_header\n";

  const size_t floats_per_vertex = 3 + 3 + 3 * k + 1 + 3 + 4;
  std::string bytes = header;
  bytes.resize(header.size() + n * floats_per_vertex * sizeof(float));
  std::vector<float> rec(floats_per_vertex);
  for (size_t i = 0; i < n; ++i) {
    float* out = rec.data();
    for (size_t c = 0; c < 3; ++c) *out++ = cloud.means[3 * i + c];
    for (size_t c = 0; c < 3; ++c) *out++ = 0.0f;  // normals: unused by 3DGS, written as zeros
    const float* sh = cloud.sh.data() + i * k * 3;
    for (size_t c = 0; c < 3; ++c) *out++ = sh[c];
    for (size_t ch = 0; ch < 3; ++ch) {
      for (size_t coeff = 1; coeff < k; ++coeff) *out++ = sh[coeff * 3 + ch];
    }
    *out++ = cloud.opacity_logits[i];
    for (size_t c = 0; c < 3; ++c) *out++ = cloud.log_scales[3 * i + c];
    for (size_t c = 0; c < 4; ++c) *out++ = cloud.quats[4 * i + c];
    std::memcpy(bytes.data() + header.size() + i * floats_per_vertex * sizeof(float), rec.data(),
                floats_per_vertex * sizeof(float));
  }
  util::write_file_atomic(path, bytes);
}

}  // namespace s4d::io
