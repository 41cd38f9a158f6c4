#include "s4d/train/checkpoint.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "s4d/util/atomic_file.h"

namespace s4d::train {

namespace {

constexpr char kMagic[8] = {'S', '4', 'D', 'C', 'K', 'P', 'T', '1'};

template <class Vec>
struct NamedArray {
  std::string name;
  Vec* values;
};

// Every array of a state, in file order.
template <class State>
auto arrays_of(State& s) {
  using Vec = std::conditional_t<std::is_const_v<State>, const std::vector<float>, std::vector<float>>;
  auto& c = s.cloud;
  std::vector<NamedArray<Vec>> out = {{"means", &c.means},
                                 {"log_scales", &c.log_scales},
                                 {"quats", &c.quats},
                                 {"opacity_logits", &c.opacity_logits},
                                 {"sh", &c.sh}};
  for (uint32_t a = 0; a < model::kAttrCount; ++a) {
    out.push_back({std::string(model::attr_name(model::Attr(a))) + ".adam_m", &s.m[a]});
    out.push_back({std::string(model::attr_name(model::Attr(a))) + ".adam_v", &s.v[a]});
  }
  for (uint32_t k = 0; k < model::kStatCount; ++k) out.push_back({model::stat_name(model::Stat(k)), &s.stats[k]});
  return out;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw std::runtime_error(path.string() + ": " + what);
}

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
  const model::HostState& state = checkpoint.state;
  nlohmann::json header;
  header["meta"] = checkpoint.meta;
  header["sh_degree"] = state.cloud.sh_degree;
  header["count"] = state.cloud.size();
  std::string body;
  for (const auto& a : arrays_of(state)) {
    for (size_t i = 0; i < a.values->size(); ++i)
      if (!std::isfinite((*a.values)[i]))
        throw std::invalid_argument("checkpoint " + path.string() + ": array '" + a.name + "' holds a non-finite value at " +
                                    std::to_string(i) + "; refusing to write it");
    header["arrays"].push_back({{"name", a.name}, {"floats", a.values->size()}});
    body.append(reinterpret_cast<const char*>(a.values->data()), a.values->size() * sizeof(float));
  }
  for (const auto& [name, values] : checkpoint.extra) {
    for (size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        throw std::invalid_argument("checkpoint " + path.string() + ": array '" + name + "' holds a non-finite value at " +
                                    std::to_string(i) + "; refusing to write it");
    header["arrays"].push_back({{"name", name}, {"floats", values.size()}});
    body.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
  }
  const std::string json = header.dump();
  const uint64_t len = json.size();
  std::string file(kMagic, sizeof kMagic);
  file.append(reinterpret_cast<const char*>(&len), sizeof len);
  file += json;
  file += body;
  util::write_file_atomic(path, file);
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the checkpoint (missing or unreadable)");
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (file.size() < 16 || std::memcmp(file.data(), kMagic, sizeof kMagic) != 0) fail(path, "not a style4d checkpoint");
  uint64_t len = 0;
  std::memcpy(&len, file.data() + 8, sizeof len);
  if (len > file.size() - 16) fail(path, "truncated header");
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(file.substr(16, len));
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("corrupt header: ") + e.what());
  }
  Checkpoint cp;
  size_t offset = 16 + len, count = 0;
  try {
    cp.meta = header.at("meta");
    cp.state.cloud.sh_degree = header.at("sh_degree").get<int>();
    count = header.at("count").get<size_t>();
    const nlohmann::json& listed = header.at("arrays");
    auto arrays = arrays_of(cp.state);
    if (listed.size() < arrays.size())
      fail(path, "lists " + std::to_string(listed.size()) + " arrays, expected at least " + std::to_string(arrays.size()));
    for (size_t k = 0; k < listed.size(); ++k) {
      const std::string name = listed[k].at("name").get<std::string>();
      const size_t floats = listed[k].at("floats").get<size_t>();
      if (k < arrays.size() && name != arrays[k].name)
        fail(path, "array " + std::to_string(k) + " is '" + name + "', expected '" + arrays[k].name + "'");
      if (floats > (file.size() - offset) / sizeof(float)) fail(path, "truncated in array '" + name + "'");
      std::vector<float>* values = k < arrays.size() ? arrays[k].values : &cp.extra.emplace_back(name, std::vector<float>{}).second;
      values->resize(floats);
      std::memcpy(values->data(), file.data() + offset, floats * sizeof(float));
      offset += floats * sizeof(float);
      for (size_t i = 0; i < floats; ++i)
        if (!std::isfinite((*values)[i])) fail(path, "array '" + name + "' holds a non-finite value at " + std::to_string(i));
    }
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("malformed header: ") + e.what());
  }
  if (offset != file.size()) fail(path, std::to_string(file.size() - offset) + " unexpected bytes after the arrays");
  const int degree = cp.state.cloud.sh_degree;
  if (degree < 0 || degree > 3) fail(path, "sh_degree " + std::to_string(degree) + " is not 0..3");
  const size_t widths[model::kAttrCount] = {3, 3, 4, 1, size_t((degree + 1) * (degree + 1)) * 3};
  for (const auto& a : arrays_of(cp.state)) {
    size_t expected = count;
    for (uint32_t k = 0; k < model::kAttrCount; ++k)
      if (a.name.rfind(model::attr_name(model::Attr(k)), 0) == 0) expected = count * widths[k];
    if (a.values->size() != expected)
      fail(path, "array '" + a.name + "' holds " + std::to_string(a.values->size()) + " floats, expected " +
                     std::to_string(expected) + " for " + std::to_string(count) + " Gaussians");
  }
  return cp;
}

}  // namespace s4d::train
