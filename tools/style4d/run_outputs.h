// Outputs of the commands that read a run (export-ply, view) must not land on the run's own files:
// `export-ply --out RUN/checkpoint/state.s4dckpt` would replace the checkpoint that run resumes from.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>

#include "args.h"
#include "s4d/run/run_dir.h"

namespace s4d::tools {

// Throws cli::UsageError "--OPTION: PATH is inside RUN's own files (...); choose another path".
inline void refuse_run_output(const std::filesystem::path& out, const std::filesystem::path& run, const std::string& option) {
  if (run::RunDir{run}.owns(out)) {
    throw cli::UsageError("--" + option + ": " + out.string() + " is one of " + run.string() +
                                "'s own files (run.json, train.json, loss.csv, checkpoint/, geometry/, eval/, style/); "
                                "choose another path");
  }
}

}  // namespace s4d::tools
