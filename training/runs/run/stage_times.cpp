#include "s4d/run/stage_times.h"

namespace s4d::run {

nlohmann::json stage_ms_json(const engine::StageTotals& t, uint64_t iterations) {
  const auto per = [&](double ms) { return iterations > 0 ? ms / static_cast<double>(iterations) : 0.0; };
  nlohmann::json stages = nlohmann::json::object();
  for (size_t i = 0; i < t.stages.size(); ++i) stages[t.stages[i]] = {{"ms", t.ms[i]}, {"ms_per_iteration", per(t.ms[i])}};
  stages["other"] = {{"ms", t.other_ms}, {"ms_per_iteration", per(t.other_ms)}};
  const char* note =
      t.gpu ? "device time between GPU timestamps written where the recorded stage changes; host work (waits, "
              "uploads, recording) is in no stage, so the stages add up to less than step_ms"
            : "the device has no timestamps on its compute queue: host wall clock per stage, GPU work counted in "
              "the stage that waits for it (project's in sort)";
  return {{"clock", t.gpu ? "gpu timestamps" : "host wall clock"},
          {"note", note},
          {"iterations", iterations},
          {"step_ms", t.window_ms},
          {"step_ms_per_iteration", per(t.window_ms)},
          {"stages_sum_ms", t.stage_sum_ms()},
          {"stages", stages}};
}

}  // namespace s4d::run
