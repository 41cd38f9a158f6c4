// A Style4D-Bench sweep (scenes x styles x methods) as data: the manifest that `style4d sweep plan`
// writes (SWEEP/manifest.json) and every back end reads, and each cell's state on disk
// (SWEEP/cells/ID/state.json, log.txt). A cell is one self-contained command line of the style4d
// program with its inputs and outputs; cells run in stages (train, stylize, bench) and a cell starts
// only after the cells it names in `after` are done. docs/sweep.md describes the formats.
#pragma once
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace s4d::cli::sweep {

inline const char* const kStages[] = {"train", "stylize", "bench"};

struct Cell {
  std::string id;     // "train.SCENE.PRESET", "stylize.SCENE.PRESET.STYLE.METHOD", "bench.<same>"
  std::string stage;  // train | stylize | bench
  std::string scene, preset, style, method;  // style and method empty for train cells
  std::vector<std::string> after;            // ids of the cells that must be done first
  std::vector<std::string> command;          // argv after the program: a fresh start
  // When `resume_when` exists, `resume_command` continues the cell from its checkpoint instead.
  std::string resume_when;
  std::vector<std::string> resume_command;
  std::vector<std::string> clean;    // removed before a fresh start (a half-written output)
  std::vector<std::string> outputs;  // files that exist once the cell succeeded
};

// The Slurm settings of one stage (spec "slurm": "default" merged with the stage's object).
struct SlurmStage {
  std::string time = "01:00:00", partition, account, mem;
  int gpus = 0, cpus_per_task = 1, max_parallel = 0;  // max_parallel 0: no %N throttle
  std::vector<std::string> extra;                       // more #SBATCH lines, e.g. "--qos=normal"
};

struct Manifest {
  std::string name;
  std::filesystem::path root;     // the sweep folder (absolute)
  std::filesystem::path program;  // the style4d program the cells run (absolute)
  std::filesystem::path spec;     // the spec it was planned from
  std::map<std::string, std::string> env;  // set for every cell, e.g. LP_NUM_THREADS=1
  std::map<std::string, SlurmStage> slurm;  // per stage
  std::vector<Cell> cells;                  // in stage order: every train cell, every stylize, every bench

  const Cell& cell(const std::string& id) const;  // throws std::invalid_argument naming the id
  std::vector<const Cell*> stage_cells(const std::string& stage) const;
};

nlohmann::json to_json(const Manifest& m);
Manifest manifest_from_json(const nlohmann::json& j, const std::filesystem::path& file);

// SWEEP/manifest.json; errors name the file.
Manifest read_manifest(const std::filesystem::path& sweep_dir);
void write_manifest(const Manifest& m);

// A cell's files: SWEEP/cells/ID/{state.json,log.txt}.
std::filesystem::path cell_dir(const Manifest& m, const std::string& id);

// state.json: {"state": "running|done|failed|interrupted", "attempts": N, "resumed": bool,
// "error": "...", "exit_code": N, "seconds": S, "host": H, "slurm_job": "ID_TASK"}; null when the
// cell never started.
nlohmann::json read_state(const Manifest& m, const std::string& id);
void write_state(const Manifest& m, const std::string& id, const nlohmann::json& state);

// Done: state "done" and every output present.
bool cell_done(const Manifest& m, const Cell& c);
// "done", "running", "failed", "interrupted", "not started" or "outputs missing".
std::string cell_state(const Manifest& m, const Cell& c);

}  // namespace s4d::cli::sweep
