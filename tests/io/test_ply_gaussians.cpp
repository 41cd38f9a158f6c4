// 3DGS PLY: writer/reader round trip, and reading a file built byte by byte (independent of the
// writer) with a shuffled property order, doubles, unknown properties and extra elements.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/io/ply_header.h"

using s4d::io::GaussianCloud;
using s4d::test::append_le;
using s4d::test::TempDir;

namespace {

GaussianCloud random_cloud(size_t n, int degree, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.0f, 2.0f);
  auto fill = [&](std::vector<float>& v, size_t count) {
    v.resize(count);
    for (float& x : v) x = normal(rng);
  };
  GaussianCloud c;
  c.sh_degree = degree;
  fill(c.means, 3 * n);
  fill(c.log_scales, 3 * n);
  fill(c.quats, 4 * n);
  fill(c.opacity_logits, n);
  fill(c.sh, n * c.sh_coeffs() * 3);
  return c;
}

// Bit-exact: the format stores float32 as is, so nothing may change on the way.
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::vector<std::string> standard_names(int degree) {
  const int k = (degree + 1) * (degree + 1);
  std::vector<std::string> names = {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
  for (int j = 0; j < 3 * (k - 1); ++j) names.push_back("f_rest_" + std::to_string(j));
  for (const char* n : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"}) {
    names.push_back(n);
  }
  return names;
}

}  // namespace

TEST_CASE("PLY round trip is bit-exact at SH degrees 0 to 3, in the standard property order") {
  TempDir dir("ply_round_trip");
  for (int degree = 0; degree <= 3; ++degree) {
    CAPTURE(degree);
    const GaussianCloud in = random_cloud(50, degree, 17u + static_cast<unsigned>(degree));
    const auto path = dir / ("scene_" + std::to_string(degree) + ".ply");
    s4d::io::write_ply_gaussians(path, in);

    const GaussianCloud out = s4d::io::read_ply_gaussians(path);
    CHECK(out.sh_degree == degree);
    CHECK(out.size() == 50);
    CHECK(same_bits(out.means, in.means));
    CHECK(same_bits(out.log_scales, in.log_scales));
    CHECK(same_bits(out.quats, in.quats));
    CHECK(same_bits(out.opacity_logits, in.opacity_logits));
    CHECK(same_bits(out.sh, in.sh));

    const s4d::io::PlyHeader header = s4d::io::read_ply_header(path);
    CHECK(header.format == "binary_little_endian");
    REQUIRE(header.elements.size() == 1);
    std::vector<std::string> names;
    for (const auto& p : header.elements[0].properties) {
      CHECK(p.type == s4d::io::PlyScalar::float32);
      names.push_back(p.name);
    }
    CHECK(names == standard_names(degree));
    CHECK(std::filesystem::file_size(path) == header.data_offset + 50 * names.size() * sizeof(float));
    CHECK(s4d::io::describe_ply_header(header).find("element vertex 50") != std::string::npos);
  }
}

TEST_CASE("PLY round trip of an empty cloud") {
  TempDir dir("ply_empty");
  GaussianCloud empty;
  empty.sh_degree = 2;
  s4d::io::write_ply_gaussians(dir / "empty.ply", empty);
  const GaussianCloud out = s4d::io::read_ply_gaussians(dir / "empty.ply");
  CHECK(out.size() == 0);
  CHECK(out.sh_degree == 2);
}

TEST_CASE("PLY writer rejects inconsistent clouds") {
  TempDir dir("ply_bad_cloud");
  GaussianCloud c = random_cloud(4, 1, 3);
  c.sh.pop_back();
  CHECK_THROWS_WITH_AS(s4d::io::write_ply_gaussians(dir / "x.ply", c), doctest::Contains("sh has"),
                       std::invalid_argument);
  c = random_cloud(4, 1, 3);
  c.quats[6] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH_AS(s4d::io::write_ply_gaussians(dir / "x.ply", c), doctest::Contains("quats of vertex 1"),
                       std::invalid_argument);
  CHECK_FALSE(std::filesystem::exists(dir / "x.ply"));
}

TEST_CASE("PLY reader handles shuffled doubles, unknown properties and extra elements") {
  TempDir dir("ply_by_hand");
  constexpr int kDegree = 1;
  constexpr size_t kK = 4;  // (degree + 1)^2
  constexpr size_t kN = 3;
  // Value of canonical property j for vertex i: distinct and exact in float.
  auto value = [](size_t i, size_t j) { return static_cast<double>(i) * 64.0 + static_cast<double>(j) * 0.5 - 7.0; };

  const std::vector<std::string> canonical = standard_names(kDegree);
  struct Prop {
    std::string name;
    std::string type;
    int canonical_index;  // -1 for unknown properties
  };
  std::vector<Prop> props;
  for (size_t j = 0; j < canonical.size(); ++j) {
    const std::string& n = canonical[j];
    const bool as_double = n == "opacity" || n == "scale_0" || n == "x" || n == "f_rest_6" || n == "rot_2";
    props.push_back({n, as_double ? "double" : "float", static_cast<int>(j)});
  }
  props.push_back({"red", "uchar", -1});
  props.push_back({"confidence", "float64", -1});
  props.push_back({"label", "int16", -1});
  std::shuffle(props.begin(), props.end(), std::mt19937(5));

  std::string bytes =
      "ply\r\n"  // a Windows line ending must not matter
      "format binary_little_endian 1.0\n"
      "comment written byte by byte by test_ply_gaussians.cpp\n"
      "obj_info not a real scanner\n"
      "element camera 1\n"
      "property float focal\n"
      "property uchar id\n"
      "element face 2\n"
      "property list uchar int vertex_indices\n"
      "element vertex " +
      std::to_string(kN) + "\n";
  for (const auto& p : props) bytes += "property " + p.type + " " + p.name + "\n";
  bytes += "element trailer 1\nproperty int tag\nend_header\n";
  append_le(bytes, 500.0f);  // camera
  append_le(bytes, uint8_t{7});
  append_le(bytes, uint8_t{3});  // face 0: 3 indices
  for (int32_t v : {0, 1, 2}) append_le(bytes, v);
  append_le(bytes, uint8_t{1});  // face 1: 1 index
  append_le(bytes, int32_t{2});
  for (size_t i = 0; i < kN; ++i) {
    for (const auto& p : props) {
      const double v = p.canonical_index >= 0 ? value(i, static_cast<size_t>(p.canonical_index)) : 1e30;
      if (p.type == "double" || p.type == "float64") {
        append_le(bytes, v);
      } else if (p.type == "float") {
        append_le(bytes, static_cast<float>(v));
      } else if (p.type == "uchar") {
        append_le(bytes, uint8_t{200});
      } else {
        append_le(bytes, int16_t{-3});
      }
    }
  }
  append_le(bytes, int32_t{42});  // trailer
  s4d::test::write_raw(dir / "by_hand.ply", bytes);

  const GaussianCloud c = s4d::io::read_ply_gaussians(dir / "by_hand.ply");
  REQUIRE(c.size() == kN);
  REQUIRE(c.sh_degree == kDegree);
  auto at = [&](size_t i, const std::string& name) {
    const size_t j = static_cast<size_t>(std::find(canonical.begin(), canonical.end(), name) - canonical.begin());
    return static_cast<float>(value(i, j));
  };
  // Every expected value is exact in float and the reader only converts, so equality is exact.
  for (size_t i = 0; i < kN; ++i) {
    CAPTURE(i);
    for (size_t c3 = 0; c3 < 3; ++c3) {
      CHECK(c.means[3 * i + c3] == at(i, std::string(1, "xyz"[c3])));
      CHECK(c.log_scales[3 * i + c3] == at(i, "scale_" + std::to_string(c3)));
      CHECK(c.sh[(i * kK + 0) * 3 + c3] == at(i, "f_dc_" + std::to_string(c3)));
    }
    for (size_t q = 0; q < 4; ++q) CHECK(c.quats[4 * i + q] == at(i, "rot_" + std::to_string(q)));
    CHECK(c.opacity_logits[i] == at(i, "opacity"));
    // f_rest is channel-major in the file: f_rest_j is channel j / (K-1), coefficient 1 + j % (K-1).
    CHECK(c.sh[(i * kK + 1) * 3 + 2] == at(i, "f_rest_" + std::to_string(2 * (kK - 1) + 0)));
    CHECK(c.sh[(i * kK + 3) * 3 + 0] == at(i, "f_rest_2"));
    CHECK(c.sh[(i * kK + 2) * 3 + 1] == at(i, "f_rest_4"));
    for (size_t j = 0; j < 3 * (kK - 1); ++j) {
      CHECK(c.sh[(i * kK + 1 + j % (kK - 1)) * 3 + j / (kK - 1)] == at(i, "f_rest_" + std::to_string(j)));
    }
  }

  const s4d::io::PlyHeader header = s4d::io::read_ply_header(dir / "by_hand.ply");
  CHECK(header.comments.size() == 2);
  CHECK(header.elements.size() == 4);
  CHECK(header.elements[1].has_list());
}
