#include "s4d/stylizer_train/checkpoint.h"

#include <map>
#include <span>
#include <stdexcept>

#include "s4d/io/safetensors.h"

namespace s4d::stylizer_train {

namespace {

namespace fs = std::filesystem;

int parse_step(const fs::path& path, const std::string& text) {
  size_t used = 0;
  int step = -1;
  try {
    step = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || step < 0)
    throw std::runtime_error(path.string() + ": metadata step '" + text + "' is not a step count");
  return step;
}

std::vector<float> read_flat(const io::SafetensorsFile& file, const std::string& name, const engine::Buffer& buffer) {
  return file.read(name, {static_cast<int64_t>(buffer.size() / sizeof(float))});
}

}  // namespace

void write_checkpoint(engine::Context& ctx, const fs::path& path, const CheckpointState& state,
                      const std::vector<optim::AdamTensor>& moments, const std::vector<CheckpointTensor>& kept) {
  std::vector<io::NamedTensor> tensors;
  for (const CheckpointTensor& t : kept) {
    const size_t n = t.buffer->size() / sizeof(float);
    tensors.push_back({t.name, {static_cast<int64_t>(n)}, ctx.download<float>(*t.buffer, n)});
  }
  for (const optim::AdamTensor& t : moments)
    for (auto& [name, values] : t.download_moments(optim::MomentNames::pytorch))
      tensors.push_back({name, {static_cast<int64_t>(values.size())}, std::move(values)});
  const fs::path tmp = path.string() + ".tmp";
  std::map<std::string, std::string> meta{{"step", std::to_string(state.step)}, {"losses", state.losses}};
  for (const auto& [key, value] : state.settings) meta[key] = value;
  io::write_safetensors(tmp, tensors, io::TensorDtype::f32, meta);
  fs::rename(tmp, path);
}

CheckpointState read_checkpoint_state(const fs::path& path, const std::vector<std::string>& keys) {
  const io::SafetensorsFile file(path);
  const std::map<std::string, std::string>& meta = file.metadata();
  std::vector<std::string> wanted = {"step", "losses"};
  wanted.insert(wanted.end(), keys.begin(), keys.end());
  for (const std::string& key : wanted)
    if (!meta.count(key)) throw std::runtime_error(path.string() + ": metadata has no " + key);
  CheckpointState state{parse_step(path, meta.at("step")), meta.at("losses"), {}};
  for (const std::string& key : keys) state.settings.emplace_back(key, meta.at(key));
  return state;
}

void read_checkpoint_moments(const fs::path& path, std::vector<optim::AdamTensor>& moments) {
  const io::SafetensorsFile file(path);
  for (optim::AdamTensor& t : moments) {
    std::vector<float> held;  // the array `find` returned last
    auto find = [&](const std::string& name) -> const std::vector<float>& {
      held = file.read(name, {static_cast<int64_t>(t.floats())});
      return held;
    };
    t.upload_moments(optim::MomentNames::pytorch, find, path.string());
  }
}

void read_checkpoint_tensors(engine::Context& ctx, const fs::path& path, const std::vector<CheckpointTensor>& tensors) {
  const io::SafetensorsFile file(path);
  for (const CheckpointTensor& t : tensors) {
    const std::vector<float> values = read_flat(file, t.name, *t.buffer);
    ctx.upload(*t.buffer, std::span<const float>(values));
  }
}

int weights_step(const fs::path& path) {
  const io::SafetensorsFile file(path);
  const auto it = file.metadata().find("step");
  return it == file.metadata().end() ? -1 : parse_step(path, it->second);
}

}  // namespace s4d::stylizer_train
