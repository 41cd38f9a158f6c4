// NumPy .npy reading and writing: round trip, a float32 file built byte by byte as numpy writes
// it, and bad files.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "s4d/data/npy.h"

namespace fs = std::filesystem;

namespace {
fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / "s4d_npy_test";
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST_CASE("npy round trip of a poses_bounds-shaped array") {
  s4d::data::NpyArray a{{3, 17}, {}};
  for (int i = 0; i < 51; ++i) a.values.push_back(0.25 * i - 3.0);
  const fs::path p = temp_dir() / "poses_bounds.npy";
  s4d::data::write_npy(p, a);
  const auto b = s4d::data::read_npy(p);
  CHECK(b.shape == a.shape);
  CHECK(b.values == a.values);  // exact: float64 both ways
  CHECK(fs::file_size(p) % 64 == 51 * 8 % 64);  // header padded to 64 bytes
}

TEST_CASE("npy float32 version 1.0 as numpy writes it") {
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
  bytes += static_cast<char>(header.size()), bytes += '\0';
  bytes += header;
  for (float f : {1.5f, -2.0f, 0.125f, 3.0f}) {
    char b[4];
    std::memcpy(b, &f, 4);
    bytes.append(b, 4);
  }
  const fs::path p = temp_dir() / "f4.npy";
  std::ofstream(p, std::ios::binary) << bytes;
  const auto a = s4d::data::read_npy(p);
  CHECK(a.shape == std::vector<size_t>{2, 2});
  CHECK(a.values == std::vector<double>{1.5, -2.0, 0.125, 3.0});

  std::ofstream(p, std::ios::binary) << bytes.substr(0, bytes.size() - 3);
  CHECK_THROWS_WITH_AS(s4d::data::read_npy(p), doctest::Contains("truncated"), std::runtime_error);
  std::ofstream(p, std::ios::binary) << "not numpy at all";
  CHECK_THROWS_WITH_AS(s4d::data::read_npy(p), doctest::Contains("bad magic"), std::runtime_error);
  CHECK_THROWS_WITH_AS(s4d::data::read_npy(temp_dir() / "missing.npy"), doctest::Contains("missing.npy"),
                       std::runtime_error);
}
