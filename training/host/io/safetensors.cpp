#include "s4d/io/safetensors.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "file_read.h"
#include "s4d/io/half_float.h"
#include "s4d/util/atomic_file.h"

namespace s4d::io {

static_assert(std::endian::native == std::endian::little, "safetensors data is little-endian");

namespace {

using detail::fail;
using nlohmann::json;

// The reference implementation refuses headers over 100 MB; so do we, before allocating.
constexpr uint64_t kMaxHeaderBytes = 100'000'000;

// Bytes per element of every dtype the format defines (0: not one of them).
size_t dtype_bytes(const std::string& dtype) {
  static const std::map<std::string, size_t> sizes = {
      {"BOOL", 1}, {"U8", 1},  {"I8", 1},  {"F8_E5M2", 1}, {"F8_E4M3", 1}, {"I16", 2}, {"U16", 2}, {"F16", 2},
      {"BF16", 2}, {"I32", 4}, {"U32", 4}, {"F32", 4},     {"F64", 8},     {"I64", 8}, {"U64", 8}};
  const auto it = sizes.find(dtype);
  return it == sizes.end() ? 0 : it->second;
}

const char* dtype_name(TensorDtype d) { return d == TensorDtype::f32 ? "F32" : d == TensorDtype::f16 ? "F16" : "BF16"; }

// Product of the dimensions; -1 past 2^62 (a hostile header).
int64_t element_count(const std::vector<int64_t>& shape) {
  int64_t n = 1;
  for (const int64_t d : shape) {
    if (d != 0 && n > (int64_t{1} << 62) / d) return -1;
    n *= d;
  }
  return n;
}

uint16_t load_u16(const char* p) {
  uint16_t v;
  std::memcpy(&v, p, 2);
  return v;
}

}  // namespace

std::string shape_text(const std::vector<int64_t>& shape) {
  std::string s = "[";
  for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + "]";
}

SafetensorsFile::SafetensorsFile(const std::filesystem::path& path)
    : path_(path), bytes_(detail::read_whole_file(path)) {
  if (bytes_.size() < 8)
    fail(path, "truncated: " + std::to_string(bytes_.size()) + " bytes, less than the 8-byte header length");
  uint64_t header_bytes = 0;
  std::memcpy(&header_bytes, bytes_.data(), 8);
  if (header_bytes > kMaxHeaderBytes)
    fail(path, "bad header: its length " + std::to_string(header_bytes) + " is over 100 MB");
  if (header_bytes > bytes_.size() - 8)
    fail(path, "truncated: the header is " + std::to_string(header_bytes) + " bytes, the file holds " +
                   std::to_string(bytes_.size() - 8) + " after the length");
  data_start_ = 8 + header_bytes;
  json header;
  try {
    header = json::parse(bytes_.begin() + 8, bytes_.begin() + static_cast<std::ptrdiff_t>(data_start_));
  } catch (const json::exception& e) {
    fail(path, std::string("bad header: not JSON (") + e.what() + ")");
  }
  if (!header.is_object()) fail(path, "bad header: not a JSON object");
  const uint64_t data_bytes = bytes_.size() - data_start_;
  for (const auto& [name, value] : header.items()) {
    if (name == "__metadata__") {
      if (!value.is_object()) fail(path, "bad header: __metadata__ is not an object");
      for (const auto& [key, text] : value.items()) {
        if (!text.is_string()) fail(path, "bad header: __metadata__ value '" + key + "' is not a string");
        metadata_[key] = text.get<std::string>();
      }
      continue;
    }
    const std::string where = "bad header: tensor '" + name + "' ";
    if (!value.is_object() || !value.contains("dtype") || !value.contains("shape") || !value.contains("data_offsets"))
      fail(path, where + "needs dtype, shape and data_offsets");
    const json &dtype = value["dtype"], &shape = value["shape"], &offsets = value["data_offsets"];
    if (!dtype.is_string() || dtype_bytes(dtype.get<std::string>()) == 0)
      fail(path, where + "has an unknown dtype " + dtype.dump());
    if (!shape.is_array() ||
        !std::all_of(shape.begin(), shape.end(), [](const json& d) { return d.is_number_unsigned(); }))
      fail(path, where + "has a shape that is not a list of non-negative integers");
    if (!offsets.is_array() || offsets.size() != 2 || !offsets[0].is_number_unsigned() ||
        !offsets[1].is_number_unsigned())
      fail(path, where + "has data_offsets that are not two non-negative integers");
    Entry e{dtype.get<std::string>(), {}, offsets[0].get<uint64_t>(), offsets[1].get<uint64_t>()};
    for (const json& d : shape) e.shape.push_back(d.get<int64_t>());
    const int64_t count = element_count(e.shape);
    if (e.begin > e.end || count < 0 || e.end - e.begin != static_cast<uint64_t>(count) * dtype_bytes(e.dtype))
      fail(path, where + "has data_offsets [" + std::to_string(e.begin) + ", " + std::to_string(e.end) +
                     "], which do not hold " + shape_text(e.shape) + " " + e.dtype);
    if (e.end > data_bytes)
      fail(path, "truncated: tensor '" + name + "' ends at data byte " + std::to_string(e.end) + ", the file holds " +
                     std::to_string(data_bytes));
    tensors_.emplace(name, std::move(e));
  }
}

std::vector<std::string> SafetensorsFile::names() const {
  std::vector<std::string> out;
  for (const auto& [name, e] : tensors_) out.push_back(name);
  return out;
}

const SafetensorsFile::Entry& SafetensorsFile::entry(const std::string& name) const {
  const auto it = tensors_.find(name);
  if (it != tensors_.end()) return it->second;
  std::string held;
  size_t listed = 0;
  for (const auto& [n, e] : tensors_) {
    if (++listed > 8) {
      held += ", ...";
      break;
    }
    held += (held.empty() ? "" : ", ") + n;
  }
  fail(path_, "no tensor '" + name + "' (it holds " + std::to_string(tensors_.size()) + " tensors: " + held + ")");
}

const std::vector<int64_t>& SafetensorsFile::shape(const std::string& name) const { return entry(name).shape; }

std::vector<float> SafetensorsFile::read(const std::string& name, const std::vector<int64_t>& expected_shape) const {
  const Entry& e = entry(name);
  if (e.shape != expected_shape)
    fail(path_, "tensor '" + name + "' has shape " + shape_text(e.shape) + ", expected " + shape_text(expected_shape));
  if (e.dtype != "F32" && e.dtype != "F16" && e.dtype != "BF16")
    fail(path_, "tensor '" + name + "' is " + e.dtype + ", expected F32, F16 or BF16");
  const size_t n = static_cast<size_t>(element_count(e.shape));
  const char* src = bytes_.data() + data_start_ + e.begin;
  std::vector<float> out(n);
  for (size_t i = 0; i < n; ++i) {
    if (e.dtype == "F32")
      std::memcpy(&out[i], src + 4 * i, 4);
    else if (e.dtype == "F16")
      out[i] = half_to_float(load_u16(src + 2 * i));
    else
      out[i] = bf16_to_float(load_u16(src + 2 * i));
    if (!std::isfinite(out[i]))
      fail(path_, "tensor '" + name + "' holds a non-finite value (" + std::to_string(out[i]) + ") at element " +
                      std::to_string(i));
  }
  return out;
}

void write_safetensors(const std::filesystem::path& path, const std::vector<NamedTensor>& tensors, TensorDtype dtype,
                       const std::map<std::string, std::string>& metadata) {
  json header = json::object();
  if (!metadata.empty()) header["__metadata__"] = metadata;
  std::string data;
  std::set<std::string> seen;
  for (const NamedTensor& t : tensors) {
    if (t.name.empty() || t.name == "__metadata__" || !seen.insert(t.name).second)
      throw std::invalid_argument("write_safetensors: tensor name '" + t.name + "' is empty, reserved or repeated");
    if (element_count(t.shape) != static_cast<int64_t>(t.values.size()))
      throw std::invalid_argument("write_safetensors: tensor '" + t.name + "' has " + std::to_string(t.values.size()) +
                                  " values for shape " + shape_text(t.shape));
    const size_t begin = data.size();
    for (const float v : t.values) {
      if (dtype == TensorDtype::f32) {
        data.append(reinterpret_cast<const char*>(&v), 4);
      } else {
        const uint16_t h = dtype == TensorDtype::f16 ? float_to_half(v) : float_to_bf16(v);
        data.append(reinterpret_cast<const char*>(&h), 2);
      }
    }
    header[t.name] = {{"dtype", dtype_name(dtype)}, {"shape", t.shape}, {"data_offsets", {begin, data.size()}}};
  }
  std::string text = header.dump();
  text.append((8 - text.size() % 8) % 8, ' ');  // the reference writer pads the header to 8 bytes
  const uint64_t length = text.size();
  std::string file(reinterpret_cast<const char*>(&length), 8);
  util::write_file_atomic(path, file + text + data);
}

}  // namespace s4d::io
