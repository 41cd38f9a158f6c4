// Trainer::Impl's field, snapshots and checkpoints.
#include <algorithm>
#include <optional>
#include <stdexcept>

#include "s4d/deform/field_parts.h"
#include "s4d/deform/motion_split.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/train/split_state.h"
#include "trainer_impl.h"

namespace s4d::train {

void Trainer::Impl::make_field(uint32_t seed) {
  if (config.fine_iterations == 0) return;
  try {
    field = std::make_unique<deform::DeformationField>(ctx, run::field_config(config, aabb_min, aabb_max), seed, "deformation field");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " (the 4DGS stage of preset '" + config.preset +
                             "'; --preset fast fits lavapipe, --stage static trains without it)");
  }
  field_planes = optim::AdamTensor(ctx, "field.planes", field->planes(), &field->v_planes(), field->plane_floats());
  field_mlp = optim::AdamTensor(ctx, "field.mlp", field->mlp(), &field->v_mlp(), field->mlp_floats());
}

nlohmann::json Trainer::Impl::meta(double seconds) const {
  nlohmann::json j = {{"stage", run::stage_name(stage)}, {"iteration", iteration},   {"lr_scale", recovery.lr_scale},   {"seconds", seconds},
          {"rollbacks", recovery.rollbacks}, {"sampler", sampler.save()}, {"aabb_min", aabb_min}, {"aabb_max", aabb_max},
          {"static_test", static_scores}, {"deform_evaluations", deform_evaluations},
          {"deform_evaluations_unmasked", deform_evaluations_unmasked}, {"densify_log", densify_log},
          {"prune_floor", prune_floor}, {"prune_floor_why", prune_floor_why},
          {"guard_repairs", recovery.repairs}, {"guard_removed", recovery.removed}, {"field_fitted", field_fitted},
          {"field_resolution", config.field_resolution}};
  if (config.time_budget > 0) j["time_budget"] = time_plan.to_json();
  return j;
}

model::Checkpoint Trainer::Impl::snapshot(double seconds) const {
  model::Checkpoint cp{meta(seconds), gaussians->download(), {}};
  if (field) {
    cp.extra = {{"field.planes", field->download_planes()}, {"field.mlp", field->download_mlp()}};
    for (const optim::AdamTensor* t : {&field_planes, &field_mlp})
      for (auto& moment : t->download_moments(optim::MomentNames::trainer)) cp.extra.push_back(std::move(moment));
    if (still_count > 0) {
      const std::vector<uint32_t> mask = deform::tail_mask(gaussians->size(), still_count);
      cp.extra.emplace_back("field.static_mask", std::vector<float>(mask.begin(), mask.end()));
    }
  }
  return cp;
}

void Trainer::Impl::restore(const model::Checkpoint& cp) {
  gaussians = std::make_unique<model::TrainableGaussians>(ctx, cp.state, "gaussians");
  sized_for = UINT32_MAX;
  const std::string stage_in_file = cp.meta.at("stage").get<std::string>();
  const std::optional<run::Stage> known = run::parse_stage(stage_in_file);
  if (!known) throw std::runtime_error("checkpoint: meta 'stage' = '" + stage_in_file + "' is not static or fine");
  stage = *known;
  iteration = cp.meta.at("iteration").get<uint32_t>();
  recovery.lr_scale = cp.meta.at("lr_scale").get<double>();
  recovery.rollbacks = cp.meta.at("rollbacks").get<uint32_t>();
  // Checkpoints written before the guard removed Gaussians have no counts: none removed.
  recovery.repairs = cp.meta.value("guard_repairs", 0u);
  recovery.removed = cp.meta.value("guard_removed", 0u);
  // Checkpoints written before time budgets have no plans: none made yet.
  if (cp.meta.contains("time_budget")) time_plan = BudgetState::from_json(cp.meta.at("time_budget"));
  sampler = stage_sampler();
  sampler.load(cp.meta.at("sampler").get<std::string>());
  static_scores = cp.meta.at("static_test");
  deform_evaluations = cp.meta.at("deform_evaluations").get<double>();
  deform_evaluations_unmasked = cp.meta.at("deform_evaluations_unmasked").get<double>();
  // Checkpoints written before the log and the floor existed have neither: the floor is measured again.
  densify_log = cp.meta.value("densify_log", nlohmann::json::array());
  prune_floor = cp.meta.value("prune_floor", 0u);
  prune_floor_why = cp.meta.value("prune_floor_why", nlohmann::json());
  still_count = 0;
  // The box and resolution may differ from the field's: the checkpoint was written before or after
  // the fit to what moves (field_box.h; checkpoints from before it have neither key: not fitted).
  field_fitted = cp.meta.value("field_fitted", false);
  const auto box_min = cp.meta.at("aabb_min").get<std::array<float, 3>>();
  const auto box_max = cp.meta.at("aabb_max").get<std::array<float, 3>>();
  const auto resolution = cp.meta.value("field_resolution", config.field_resolution);
  if (resolution != config.field_resolution) {
    config.field_resolution = resolution;
    save_run_json();  // an older checkpoint than run.json's settings (the newest was damaged)
  }
  if (!field || box_min != aabb_min || box_max != aabb_max || field->config().resolution != config.field_resolution) {
    aabb_min = box_min, aabb_max = box_max;
    make_field(config.seed);
  }
  if (!field) return;
  auto extra = [&](const std::string& name) -> const std::vector<float>& {
    return checkpoint_array(cp, name, "checkpoint (the run trains a deformation field)");
  };
  field->upload_planes(extra("field.planes"));
  field->upload_mlp(extra("field.mlp"));
  for (optim::AdamTensor* t : {&field_planes, &field_mlp}) t->upload_moments(optim::MomentNames::trainer, extra, "checkpoint");
  for (const auto& [name, values] : cp.extra) {
    if (name != "field.static_mask") continue;
    if (values.size() != gaussians->size())
      throw std::runtime_error("checkpoint: field.static_mask holds " + std::to_string(values.size()) + " entries for " +
                               std::to_string(gaussians->size()) + " Gaussians");
    apply_mask(std::vector<uint32_t>(values.begin(), values.end()));  // checkpoints since the split: already in order
  }
}

Divergence Trainer::Impl::divergence(const model::Checkpoint& state) const {
  return find_divergence(state, [this](const std::string& array, uint64_t index) {
    const bool planes = array.rfind("field.planes", 0) == 0;
    return field ? (planes ? deform::plane_part(field->shape(), index) : deform::mlp_part(field->shape(), index)) : "";
  });
}

void Trainer::Impl::remove_gaussians(const std::vector<uint32_t>& rows, double seconds) {
  model::Checkpoint cp = snapshot(seconds);
  cp.state = train::remove_gaussians(cp.state, rows);
  std::erase_if(cp.extra, [](const auto& e) { return e.first == "field.static_mask"; });
  restore(cp);
}

void Trainer::Impl::save_run_json() const {
  run::RunJson saved = run::read_run_json(run);
  saved.settings = config;
  saved.dataset = facts;
  run::write_run_json(run, saved);
}

void Trainer::Impl::checkpoint(double seconds) {
  model::Checkpoint cp = snapshot(seconds);
  Divergence d = divergence(cp);
  save_checked(std::move(cp), std::move(d), [&](const model::Checkpoint& saved) {
    model::write_checkpoint_rotating(run.checkpoint(), run.previous_checkpoint(), saved, !newest_damaged);
    newest_damaged = false;
    io::write_ply_gaussians(run.gaussians_ply(), saved.state.cloud);
  });
}

}  // namespace s4d::train
