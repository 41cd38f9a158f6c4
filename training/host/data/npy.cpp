#include "s4d/data/npy.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>

#include "s4d/util/atomic_file.h"

namespace s4d::data {
namespace {

static_assert(std::endian::native == std::endian::little, "the .npy reader assumes a little-endian host");

constexpr char kMagic[] = "\x93NUMPY";

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw std::runtime_error(path.string() + ": " + what);
}

std::string read_all(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "cannot open");
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The header is a Python dict literal: {'descr': '<f8', 'fortran_order': False, 'shape': (3, 17), }
std::string dict_value(const std::filesystem::path& path, const std::string& header, const std::string& key) {
  const std::regex re("'" + key + "'\\s*:\\s*('[^']*'|True|False|\\([^)]*\\))");
  std::smatch m;
  if (!std::regex_search(header, m, re)) fail(path, "header has no '" + key + "'");
  return m[1].str();
}

}  // namespace

NpyArray read_npy(const std::filesystem::path& path) {
  const std::string bytes = read_all(path);
  if (bytes.size() < 10 || bytes.compare(0, 6, kMagic, 6) != 0) fail(path, "not a NumPy .npy file (bad magic)");
  const int major = static_cast<unsigned char>(bytes[6]);
  size_t header_len = 0, offset = 0;
  if (major == 1) {
    header_len = static_cast<unsigned char>(bytes[8]) | static_cast<size_t>(static_cast<unsigned char>(bytes[9])) << 8;
    offset = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) fail(path, "truncated header");
    for (int k = 0; k < 4; ++k) header_len |= static_cast<size_t>(static_cast<unsigned char>(bytes[8 + k])) << (8 * k);
    offset = 12;
  } else {
    fail(path, "unsupported .npy format version " + std::to_string(major));
  }
  if (bytes.size() < offset + header_len) fail(path, "truncated header");
  const std::string header = bytes.substr(offset, header_len);
  const std::string descr = dict_value(path, header, "descr");
  if (dict_value(path, header, "fortran_order") != "False") fail(path, "Fortran-ordered arrays are not supported");
  size_t item = 0;
  if (descr == "'<f8'") item = 8;
  else if (descr == "'<f4'") item = 4;
  else fail(path, "dtype " + descr + " is not supported (expected little-endian float64 '<f8' or float32 '<f4')");

  NpyArray out;
  const std::string shape = dict_value(path, header, "shape");
  std::regex num("\\d+");
  for (auto it = std::sregex_iterator(shape.begin(), shape.end(), num); it != std::sregex_iterator(); ++it)
    out.shape.push_back(std::stoull(it->str()));
  size_t count = 1;
  for (size_t d : out.shape) count *= d;
  const size_t data = offset + header_len;
  if (bytes.size() - data < count * item)
    fail(path, "truncated: shape " + shape + " needs " + std::to_string(count * item) + " bytes of data, " +
                   std::to_string(bytes.size() - data) + " present");
  out.values.resize(count);
  for (size_t i = 0; i < count; ++i) {
    if (item == 8) {
      std::memcpy(&out.values[i], bytes.data() + data + 8 * i, 8);
    } else {
      float f = 0;
      std::memcpy(&f, bytes.data() + data + 4 * i, 4);
      out.values[i] = f;
    }
  }
  return out;
}

void write_npy(const std::filesystem::path& path, const NpyArray& array) {
  size_t count = 1;
  std::string shape = "(";
  for (size_t d : array.shape) shape += std::to_string(d) + ", ", count *= d;
  if (array.shape.size() > 1) shape.resize(shape.size() - 2);
  else if (array.shape.size() == 1) shape.resize(shape.size() - 1);
  shape += ")";
  if (count != array.values.size())
    throw std::invalid_argument(path.string() + ": shape " + shape + " does not match " +
                                std::to_string(array.values.size()) + " values");
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': " + shape + ", }";
  // Pad with spaces so magic + lengths + header + newline is a multiple of 64 bytes.
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string bytes(kMagic, 6);
  bytes += '\x01';
  bytes += '\x00';
  bytes += static_cast<char>(header.size() & 0xFF);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  const size_t start = bytes.size();
  bytes.resize(start + 8 * count);
  std::memcpy(bytes.data() + start, array.values.data(), 8 * count);
  util::write_file_atomic(path, bytes);
}

}  // namespace s4d::data
