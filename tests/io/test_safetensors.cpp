// safetensors: reading files laid out by hand (as the Python library writes them), the writer's
// round trip in F32 / F16 / BF16, and every reader error naming the file and the tensor.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "s4d/io/safetensors.h"

using s4d::io::NamedTensor;
using s4d::io::SafetensorsFile;
using s4d::io::TensorDtype;
using s4d::test::append_le;
using s4d::test::error_at;
using s4d::test::TempDir;

namespace {

// A file from a header text and raw data bytes, laid out without the library under test.
std::string file_bytes(const std::string& header, const std::string& data) {
  std::string b;
  append_le(b, static_cast<uint64_t>(header.size()));
  return b + header + data;
}

std::string floats_le(const std::vector<float>& values) {
  std::string b;
  for (const float v : values) append_le(b, v);
  return b;
}

const std::string kOneTensor = R"({"w":{"dtype":"F32","shape":[2],"data_offsets":[0,8]}})";

// Opening (or, with `tensor`, reading that tensor of shape `shape` from) `bytes` fails with "<path>: <expected>".
void check_fails(const std::string& bytes, const std::string& expected, const std::string& tensor = "",
                 const std::vector<int64_t>& shape = {}) {
  TempDir dir("safetensors_errors");
  const auto path = dir / "weights.safetensors";
  s4d::test::write_raw(path, bytes);
  if (tensor.empty()) {
    CHECK_THROWS_WITH_AS(SafetensorsFile{path}, error_at(path, expected), std::runtime_error);
  } else {
    const SafetensorsFile file(path);
    CHECK_THROWS_WITH_AS(file.read(tensor, shape), error_at(path, expected), std::runtime_error);
  }
}

}  // namespace

TEST_CASE("safetensors reader reads a file laid out by hand, metadata and all dtypes it converts") {
  TempDir dir("safetensors_hand");
  std::string data = floats_le({1.5f, -2.0f, 0.25f, 8.0f, 3.0f, -0.5f});
  // F16: 1, -2, 2^-24, 65504; BF16: 1.5, -4.
  for (const int h : {0x3c00, 0xc000, 0x0001, 0x7bff}) append_le(data, static_cast<uint16_t>(h));
  for (const int b : {0x3fc0, 0xc080}) append_le(data, static_cast<uint16_t>(b));
  const std::string header =
      R"({"__metadata__":{"format":"pt"},"0.weight":{"dtype":"F32","shape":[2,3],"data_offsets":[0,24]},)"
      R"("half":{"dtype":"F16","shape":[4],"data_offsets":[24,32]},"brain":{"dtype":"BF16","shape":[2,1],"data_offsets":[32,36]}})";
  s4d::test::write_raw(dir / "w.safetensors", file_bytes(header, data));
  const SafetensorsFile file(dir / "w.safetensors");
  CHECK(file.names() == std::vector<std::string>{"0.weight", "brain", "half"});
  CHECK(file.metadata().at("format") == "pt");
  CHECK(file.shape("0.weight") == std::vector<int64_t>{2, 3});
  CHECK(file.read("0.weight", {2, 3}) == std::vector<float>{1.5f, -2.0f, 0.25f, 8.0f, 3.0f, -0.5f});
  CHECK(file.read("half", {4}) == std::vector<float>{1.0f, -2.0f, std::ldexp(1.0f, -24), 65504.0f});
  CHECK(file.read("brain", {2, 1}) == std::vector<float>{1.5f, -4.0f});
}

TEST_CASE("safetensors writer round-trips F32 exactly and F16 / BF16 to nearest even") {
  TempDir dir("safetensors_roundtrip");
  const std::vector<float> values = {0.0f, -0.0f, 1.0f, -3.140625f, 1.0f / 3.0f, 65504.0f, 6.0e-8f, 1.0e-30f, 123.456f};
  const std::vector<NamedTensor> tensors = {{"b", {3, 3}, values}, {"a.bias", {1}, {7.0f}}, {"empty", {0, 4}, {}}};
  s4d::io::write_safetensors(dir / "f32.safetensors", tensors, TensorDtype::f32, {{"source", "test"}});
  const SafetensorsFile f32(dir / "f32.safetensors");
  CHECK(f32.read("b", {3, 3}) == values);
  CHECK(f32.read("a.bias", {1}) == std::vector<float>{7.0f});
  CHECK(f32.read("empty", {0, 4}).empty());
  CHECK(f32.metadata().at("source") == "test");

  s4d::io::write_safetensors(dir / "f16.safetensors", tensors, TensorDtype::f16);
  // 1/3 -> 0x3555; 123.456 -> 123.4375; 6e-8 -> the subnormal 2^-24; 1e-30 -> 0.
  const std::vector<float> f16 = {0.0f, -0.0f,    1.0f, -3.140625f, 0.333251953125f, 65504.0f, std::ldexp(1.0f, -24),
                                  0.0f, 123.4375f};
  CHECK(SafetensorsFile(dir / "f16.safetensors").read("b", {3, 3}) == f16);

  s4d::io::write_safetensors(dir / "bf16.safetensors", tensors, TensorDtype::bf16);
  // bf16 keeps 8 mantissa bits: 1/3 -> 0.333984375, 123.456 -> 123.5, 65504 -> 65536.
  const std::vector<float> read = SafetensorsFile(dir / "bf16.safetensors").read("b", {3, 3});
  CHECK(read[4] == 0.333984375f);
  CHECK(read[5] == 65536.0f);
  CHECK(read[8] == 123.5f);
  CHECK(std::abs(read[7] - 1.0e-30f) < 1.0e-32f);

  CHECK_THROWS_AS(s4d::io::write_safetensors(dir / "x.safetensors", {{"a", {2}, {1.0f}}}), std::invalid_argument);
  CHECK_THROWS_AS(s4d::io::write_safetensors(dir / "x.safetensors", {{"a", {1}, {1.0f}}, {"a", {1}, {1.0f}}}),
                  std::invalid_argument);
}

TEST_CASE("safetensors reader names a missing tensor, a wrong shape and a wrong dtype") {
  check_fails(file_bytes(kOneTensor, floats_le({1, 2})), "no tensor '2.weight' (it holds 1 tensors: w)", "2.weight",
              {2});
  check_fails(file_bytes(kOneTensor, floats_le({1, 2})), "tensor 'w' has shape [2], expected [1, 2]", "w", {1, 2});
  std::string ints;
  append_le(ints, int64_t{5});
  check_fails(file_bytes(R"({"n":{"dtype":"I64","shape":[1],"data_offsets":[0,8]}})", ints),
              "tensor 'n' is I64, expected F32, F16 or BF16", "n", {1});
}

TEST_CASE("safetensors reader names a non-finite value and where it is") {
  check_fails(file_bytes(kOneTensor, floats_le({1.0f, std::numeric_limits<float>::quiet_NaN()})),
              "tensor 'w' holds a non-finite value (nan) at element 1", "w", {2});
  std::string half_inf;
  append_le(half_inf, uint16_t{0x7c00});
  check_fails(file_bytes(R"({"h":{"dtype":"F16","shape":[1],"data_offsets":[0,2]}})", half_inf),
              "tensor 'h' holds a non-finite value (inf) at element 0", "h", {1});
}

TEST_CASE("safetensors reader refuses truncated files") {
  check_fails("abc", "truncated: 3 bytes, less than the 8-byte header length");
  std::string cut_header;
  append_le(cut_header, uint64_t{500});
  check_fails(cut_header + "{}", "truncated: the header is 500 bytes, the file holds 2 after the length");
  check_fails(file_bytes(kOneTensor, floats_le({1})), "truncated: tensor 'w' ends at data byte 8, the file holds 4");
}

TEST_CASE("safetensors reader refuses bad headers") {
  std::string huge;
  append_le(huge, uint64_t{1} << 40);
  check_fails(huge, "bad header: its length 1099511627776 is over 100 MB");
  check_fails(file_bytes("{\"w\": [", ""), "bad header: not JSON");
  check_fails(file_bytes("[1, 2]", ""), "bad header: not a JSON object");
  check_fails(file_bytes(R"({"w":{"dtype":"F32","shape":[2]}})", floats_le({1, 2})),
              "bad header: tensor 'w' needs dtype, shape and data_offsets");
  check_fails(file_bytes(R"({"w":{"dtype":"F31","shape":[2],"data_offsets":[0,8]}})", floats_le({1, 2})),
              "bad header: tensor 'w' has an unknown dtype \"F31\"");
  check_fails(file_bytes(R"({"w":{"dtype":"F32","shape":[2,-1],"data_offsets":[0,8]}})", floats_le({1, 2})),
              "bad header: tensor 'w' has a shape that is not a list of non-negative integers");
  check_fails(file_bytes(R"({"w":{"dtype":"F32","shape":[3],"data_offsets":[0,8]}})", floats_le({1, 2})),
              "bad header: tensor 'w' has data_offsets [0, 8], which do not hold [3] F32");
  check_fails(file_bytes(R"({"w":{"dtype":"F32","shape":[2],"data_offsets":[8]}})", floats_le({1, 2})),
              "bad header: tensor 'w' has data_offsets that are not two non-negative integers");
  check_fails(file_bytes(R"({"__metadata__":{"a":1}})", ""), "bad header: __metadata__ value 'a' is not a string");
}

TEST_CASE("safetensors reader names a missing file") {
  TempDir dir("safetensors_missing");
  CHECK_THROWS_WITH_AS(SafetensorsFile(dir / "none.safetensors"), error_at(dir / "none.safetensors", "cannot open"),
                       std::runtime_error);
}
