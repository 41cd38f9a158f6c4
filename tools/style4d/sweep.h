// The parts of `style4d sweep` (cmd_sweep.cpp): planning a spec into cells (sweep_plan.cpp),
// running one cell idempotently (sweep_cell.cpp), the back ends that run the cells (sweep_local.cpp:
// a process pool on this machine; sweep_slurm.cpp: sbatch job arrays and their status) and the
// merged table (sweep_report.cpp).
#pragma once
#include <filesystem>
#include <sys/types.h>

#include <map>
#include <string>
#include <vector>

#include "sweep_manifest.h"

namespace s4d::cli::sweep {

// The manifest of `spec_file` for the sweep folder `out`; `program` is the style4d the cells run.
// Throws "SPEC: field: why".
Manifest plan(const std::filesystem::path& spec_file, const std::filesystem::path& out, const std::filesystem::path& program);

// Runs one cell: skipped when done; refused (state failed) when a cell it needs is not done; else
// its command (or its resume command when its checkpoint exists) with stdout and stderr appended to
// SWEEP/cells/ID/log.txt. Records state.json. Returns 0 when the cell is done, 130 when it was
// interrupted (resumable), 1 when it failed.
int run_cell(const Manifest& m, const std::string& id);

// fork + exec of `program args` with `env` added and stdout and stderr into `out_fd` (-1: inherited),
// in the folder `cwd` (empty: this process's).
pid_t spawn_process(const std::filesystem::path& program, const std::vector<std::string>& args,
                    const std::map<std::string, std::string>& env, int out_fd, const std::filesystem::path& cwd = {});

// Runs every cell not done on this machine, at most `jobs` at once, each through run_cell in its
// own process (`program sweep cell SWEEP ID`). A failed cell does not stop the others; the cells
// after it are not started. Returns the number of cells that are not done at the end.
int run_local(const Manifest& m, int jobs);

struct SlurmOptions {
  bool dry_run = false;         // write the scripts, submit nothing
  std::string sbatch = "sbatch";
};
// Writes SWEEP/slurm/<stage>.sbatch for each stage with cells to run and submits them as job arrays
// (one task per cell, logs per task in SWEEP/slurm/logs/), recorded in SWEEP/slurm/jobs.json.
// Prints each stage's job id. Returns the number of arrays submitted.
int submit_slurm(const Manifest& m, const SlurmOptions& options);

// The Slurm state of each cell of the sweep's submitted arrays (sacct, else squeue): id -> state
// such as PENDING, RUNNING, COMPLETED, FAILED, CANCELLED; empty when Slurm cannot say.
std::map<std::string, std::string> slurm_states(const Manifest& m);
// The job ids ("JOB_TASK") of the cells in SWEEP/slurm/jobs.json's latest submission of each cell.
std::map<std::string, std::string> slurm_job_ids(const Manifest& m);

// A table of every cell (stage, state, attempts, Slurm state, error) on stdout; `json` writes it as
// JSON instead. Returns the number of cells not done.
int print_status(const Manifest& m, bool json);

// SWEEP/report/: report.md (scene x method rows, the 12 Style4D-Bench metrics, best per scene in
// bold, means over the styles), report.csv, report.json, results.csv (one row per cell) and
// plots/<metric>.png; lists the bench cells that are missing. Returns the number missing.
int write_report(const Manifest& m, const std::filesystem::path& out);

}  // namespace s4d::cli::sweep
