// safetensors files (huggingface/safetensors): an 8-byte little-endian header length, a JSON header
// {"name": {"dtype": "F32", "shape": [..], "data_offsets": [begin, end]}, "__metadata__": {..}},
// then the tensors' bytes, little-endian, row-major. Network weights keep their PyTorch state-dict
// names, so a published .pth converts with one line of Python (docs/stylization.md, "Network stylizers").
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace s4d::io {

// The element types read() converts to float and write_safetensors() writes.
enum class TensorDtype { f32, f16, bf16 };

class SafetensorsFile {
 public:
  // Reads the whole file and checks its header. Throws std::runtime_error("<path>: <problem>") when
  // the file cannot be read, is truncated (shorter than its header or a tensor's data_offsets say),
  // or has a bad header (not a JSON object, an entry without dtype / shape / data_offsets, an
  // unknown dtype, or data_offsets whose length does not match shape and dtype).
  explicit SafetensorsFile(const std::filesystem::path& path);

  const std::filesystem::path& path() const { return path_; }
  std::vector<std::string> names() const;  // sorted
  bool contains(const std::string& name) const { return tensors_.count(name) != 0; }
  const std::map<std::string, std::string>& metadata() const { return metadata_; }
  // The stored shape; throws std::runtime_error naming the file and tensor when it is missing.
  const std::vector<int64_t>& shape(const std::string& name) const;

  // The tensor as float. Throws std::runtime_error naming the file and tensor when it is missing,
  // its shape is not `expected_shape`, its dtype is not F32, F16 or BF16, or a value is NaN or
  // infinite (naming the element).
  std::vector<float> read(const std::string& name, const std::vector<int64_t>& expected_shape) const;

 private:
  struct Entry {
    std::string dtype;  // as in the file: "F32", "I64", ...
    std::vector<int64_t> shape;
    uint64_t begin = 0, end = 0;  // byte range within the data section
  };
  const Entry& entry(const std::string& name) const;

  std::filesystem::path path_;
  std::string bytes_;
  size_t data_start_ = 0;
  std::map<std::string, Entry> tensors_;
  std::map<std::string, std::string> metadata_;
};

struct NamedTensor {
  std::string name;
  std::vector<int64_t> shape;
  std::vector<float> values;  // row-major, product(shape) of them
};

// Writes the tensors (in the given order) as `dtype`, rounding to nearest even, replacing `path`
// atomically. Throws std::invalid_argument for a duplicate or empty name, a name "__metadata__",
// or values that do not match the shape; std::runtime_error when writing fails.
void write_safetensors(const std::filesystem::path& path, const std::vector<NamedTensor>& tensors,
                       TensorDtype dtype = TensorDtype::f32, const std::map<std::string, std::string>& metadata = {});

// "[64, 3, 3, 3]": shapes in messages.
std::string shape_text(const std::vector<int64_t>& shape);

}  // namespace s4d::io
