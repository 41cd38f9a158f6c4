// 3DGS PLY reader errors: each names the file and the problem.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "s4d/io/ply_gaussians.h"

using s4d::test::append_le;
using s4d::test::error_at;
using s4d::test::TempDir;

namespace {

const std::vector<std::string> kDegree0 = {"x",       "y",      "z",      "nx",      "ny",      "nz",
                                           "f_dc_0",  "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1",
                                           "scale_2", "rot_0",  "rot_1",  "rot_2",   "rot_3"};

// A file whose header declares `declared` vertices with float properties `names` and whose data
// holds `written` vertices, every value 0.5 except vertex 1's `nan_property` (if given).
std::string ply_bytes(const std::vector<std::string>& names, size_t declared, size_t written,
                      const std::string& format = "binary_little_endian 1.0", const std::string& nan_property = "") {
  std::string b = "ply\nformat " + format + "\nelement vertex " + std::to_string(declared) + "\n";
  for (const auto& n : names) b += "property float " + n + "\n";
  b += "end_header\n";
  for (size_t i = 0; i < written; ++i) {
    for (const auto& n : names) {
      append_le(b, i == 1 && n == nan_property ? std::numeric_limits<float>::quiet_NaN() : 0.5f);
    }
  }
  return b;
}

// Reading `bytes` as scene.ply fails with a message containing the path and `expected`.
void check_read_fails(const std::string& bytes, const std::string& expected) {
  TempDir dir("ply_errors");
  const auto path = dir / "scene.ply";
  s4d::test::write_raw(path, bytes);
  CHECK_THROWS_WITH_AS(s4d::io::read_ply_gaussians(path), error_at(path, expected), std::runtime_error);
}

std::vector<std::string> with(std::vector<std::string> names, const std::vector<std::string>& extra) {
  names.insert(names.end(), extra.begin(), extra.end());
  return names;
}

}  // namespace

TEST_CASE("PLY reader accepts the minimal degree-0 file the error cases start from") {
  TempDir dir("ply_minimal");
  s4d::test::write_raw(dir / "ok.ply", ply_bytes(kDegree0, 2, 2));
  const auto cloud = s4d::io::read_ply_gaussians(dir / "ok.ply");
  CHECK(cloud.size() == 2);
  CHECK(cloud.sh_degree == 0);
}

TEST_CASE("PLY reader names a missing file") {
  const std::string path = "/nonexistent-dir/scene.ply";
  CHECK_THROWS_WITH_AS(s4d::io::read_ply_gaussians(path),
                       doctest::Contains("/nonexistent-dir/scene.ply: cannot open: No such file or directory"),
                       std::runtime_error);
}

TEST_CASE("PLY reader rejects wrong magic, ascii and big-endian files") {
  check_read_fails("plx\nformat binary_little_endian 1.0\nend_header\n", "not a PLY file (no 'ply' magic)");
  check_read_fails("", "not a PLY file (no 'ply' magic)");
  check_read_fails(ply_bytes(kDegree0, 1, 1, "ascii 1.0"), "format ascii is not supported");
  check_read_fails(ply_bytes(kDegree0, 1, 1, "binary_big_endian 1.0"), "format binary_big_endian is not supported");
  check_read_fails(ply_bytes(kDegree0, 1, 1, "binary_little_endian 2.0"), "PLY version 2.0 is not supported");
}

TEST_CASE("PLY reader rejects malformed headers") {
  check_read_fails("ply\nformat binary_little_endian 1.0\nelement vertex 1\n", "truncated header (no 'end_header')");
  check_read_fails("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float16 x\nend_header\n",
                   "header line 4 ('property float16 x'): unknown type 'float16'");
  check_read_fails("ply\nformat binary_little_endian 1.0\nelement vertex -1\nend_header\n",
                   "header line 3 ('element vertex -1'): count '-1' is not a non-negative integer");
  check_read_fails("ply\nformat binary_little_endian 1.0\nelement face 0\nend_header\n", "no element 'vertex'");
  check_read_fails("ply\nelement vertex 0\nend_header\n", "header has no 'format' line");
}

TEST_CASE("PLY reader names a missing property") {
  std::vector<std::string> names = kDegree0;
  names.pop_back();
  check_read_fails(ply_bytes(names, 1, 1), "missing property 'rot_3' in element 'vertex'");
}

TEST_CASE("PLY reader rejects f_rest counts other than 0, 9, 24, 45 and gaps in f_rest") {
  std::vector<std::string> rest;
  for (int j = 0; j < 12; ++j) rest.push_back("f_rest_" + std::to_string(j));
  check_read_fails(ply_bytes(with(kDegree0, rest), 1, 1),
                   "element 'vertex' has 12 f_rest_* properties; expected 0, 9, 24 or 45");
  rest.resize(9);
  rest[3] = "f_rest_9";
  check_read_fails(ply_bytes(with(kDegree0, rest), 1, 1), "missing property 'f_rest_3' in element 'vertex'");
}

TEST_CASE("PLY reader reports truncated data with the sizes") {
  // 17 floats = 68 bytes per vertex.
  check_read_fails(ply_bytes(kDegree0, 10, 5),
                   "truncated: header says 10 vertices (680 bytes) but only 340 bytes follow");
  // A corrupt count is caught before anything is sized after it.
  check_read_fails(ply_bytes(kDegree0, 1'000'000'000'000, 1),
                   "truncated: header says 1000000000000 vertices (68000000000000 bytes) but only 68 bytes follow");
  // A list element before 'vertex' is skipped item by item, and its truncation is caught too.
  std::string face_first = ply_bytes(kDegree0, 0, 0);
  face_first.insert(face_first.find("element vertex"), "element face 1\nproperty list uchar int idx\n");
  append_le(face_first, uint8_t{3});
  append_le(face_first, int32_t{0});
  check_read_fails(face_first, "truncated: element 'face' item 0 property 'idx' (12 bytes) but only 4 bytes follow");
}

TEST_CASE("PLY reader names the vertex and property of a non-finite value") {
  check_read_fails(ply_bytes(kDegree0, 3, 3, "binary_little_endian 1.0", "scale_1"),
                   "vertex 1 property 'scale_1' is not finite (nan)");
}

TEST_CASE("PLY reader rejects list properties in vertex and non-float required properties") {
  std::string list_in_vertex = ply_bytes(kDegree0, 0, 0);
  list_in_vertex.insert(list_in_vertex.find("end_header"), "property list uchar int idx\n");
  check_read_fails(list_in_vertex, "list property 'idx' in element 'vertex' is not supported");
  std::string int_x = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty int x\nend_header\n";
  check_read_fails(int_x, "property 'x' in element 'vertex' has type int; expected float or double");
}
