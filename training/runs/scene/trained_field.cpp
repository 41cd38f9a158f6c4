#include "s4d/scene/trained_field.h"

#include <stdexcept>
#include <string>

#include "s4d/run/checkpoint.h"
#include "s4d/run/names.h"
#include "s4d_deform.h"

namespace s4d::scene {
namespace {

namespace fs = std::filesystem;

template <typename T>
T meta_field(const nlohmann::json& meta, const char* key, const char* what, const fs::path& file) {
  if (!meta.is_object() || !meta.contains(key))
    throw std::runtime_error(file.string() + ": meta has no '" + key + "' (" + what + ")");
  try {
    return meta.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw std::runtime_error(file.string() + ": meta '" + key + "' is not " + what);
  }
}

std::vector<float> take_array(run::Checkpoint& cp, const std::string& name, const char* what, size_t floats,
                              const fs::path& file) {
  std::string present;
  for (auto& [n, values] : cp.extra) {
    if (n != name) {
      present += (present.empty() ? "" : ", ") + n;
      continue;
    }
    if (values.size() != floats)
      throw std::runtime_error(file.string() + ": array '" + name + "' holds " + std::to_string(values.size()) +
                               " floats but the field that run.json's settings describe needs " + std::to_string(floats));
    return std::move(values);
  }
  throw std::runtime_error(file.string() + ": no array '" + name + "' (" + what + "); the checkpoint's extra arrays are: " +
                           (present.empty() ? "none" : present) +
                           ". A 4DGS run's checkpoint holds the field from the start of training");
}

}  // namespace

TrainedField read_trained_field(const fs::path& file, const run::TrainConfig& config, const fs::path& run_root) {
  run::Checkpoint cp = run::read_checkpoint(file);
  const std::string stage = meta_field<std::string>(cp.meta, "stage", "a stage name", file);
  const uint32_t iteration = meta_field<uint32_t>(cp.meta, "iteration", "an iteration count", file);
  if (run::parse_stage(stage) != run::Stage::fine)
    throw std::runtime_error(file.string() + ": the run is incomplete: the checkpoint is from the " + stage +
                             " stage (iteration " + std::to_string(iteration) + " of " +
                             std::to_string(config.iterations) + ") and the 4DGS stage has not started; finish it "
                             "with `style4d train --run " + run_root.string() + "`");
  TrainedField out;
  out.fine_iteration = iteration;
  out.field = run::field_config(config, meta_field<std::array<float, 3>>(cp.meta, "aabb_min", "three floats", file),
                                  meta_field<std::array<float, 3>>(cp.meta, "aabb_max", "three floats", file));
  // A field fitted to what moves holds its resolution with its box (checkpoints before the fit: the settings').
  if (cp.meta.contains("field_resolution"))
    out.field.resolution = meta_field<std::array<uint32_t, 4>>(cp.meta, "field_resolution", "four whole numbers", file);
  gpu::DeformShape shape;
  try {
    shape = deform::deform_shape(out.field);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error((run_root / "run.json").string() + ": settings: " + e.what());
  }
  out.planes = take_array(cp, "field.planes", "the deformation field's HexPlanes", gpu::deform_planes_total(shape), file);
  out.mlp = take_array(cp, "field.mlp", "the deformation field's MLP", gpu::deform_mlp_total(shape), file);
  for (const auto& [name, values] : cp.extra) {
    if (name != "field.static_mask") continue;
    if (values.size() != cp.cloud.size())
      throw std::runtime_error(file.string() + ": array 'field.static_mask' holds " + std::to_string(values.size()) +
                               " entries for " + std::to_string(cp.cloud.size()) + " Gaussians");
    out.still_mask.assign(values.begin(), values.end());
  }
  out.canonical = std::move(cp.cloud);
  return out;
}

}  // namespace s4d::scene
