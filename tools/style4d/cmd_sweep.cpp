// style4d sweep plan|slurm|local|status|report|cell: a Style4D-Bench sweep (scenes x styles x
// methods) as cells that Slurm job arrays or a local process pool run unchanged, and the merged
// table (ARCHITECTURE.md "Scale beyond one machine"; docs/sweep.md).
#include <filesystem>
#include <iostream>

#include "args.h"
#include "commands.h"
#include "sweep.h"

namespace s4d::cli {

namespace {

namespace fs = std::filesystem;

const char* const kSummary =
    "A Style4D-Bench sweep (scenes x styles x methods) as cells: train each scene once, stylize it per\n"
    "style and method, bench each result. Every cell is one style4d command line with its inputs and\n"
    "outputs; a finished cell is skipped, a killed one resumes from its checkpoint, a failed one records\n"
    "its error (SWEEP/cells/ID/state.json, log.txt) without stopping the others. docs/sweep.md.\n\n"
    "  plan SPEC.json --out SWEEP   expand a sweep spec into SWEEP/manifest.json\n"
    "  slurm SWEEP [--dry-run]      submit the cells not done as sbatch job arrays, one per stage\n"
    "  local SWEEP [-j N]           run the cells not done on this machine, N at a time (default 1)\n"
    "  status SWEEP [--json]        what is done, running, failed (the cells' files, sacct/squeue)\n"
    "  report SWEEP [--out DIR]     the merged table (default SWEEP/report/) and the missing cells\n"
    "  cell SWEEP ID                run one cell (what each Slurm task and each local process runs)";

const std::vector<OptionSpec> kSpecs = {
    {"out", "plan: the sweep folder to create; report: the report folder (default SWEEP/report)", true, "DIR"},
    {"jobs", "local: cells at a time (also -j N; default 1)", true, "N"},
    {"dry-run", "slurm: write SWEEP/slurm/*.sbatch and print the sbatch commands, submit nothing", false, ""},
    {"sbatch", "slurm: the sbatch command (default sbatch)", true, "CMD"},
    {"json", "status: print JSON", false, ""},
};

std::vector<std::string> expand_short_jobs(const std::vector<std::string>& argv) {
  std::vector<std::string> out;
  for (const std::string& a : argv) {
    if (a == "-j") out.push_back("--jobs");
    else if (a.size() > 2 && a.rfind("-j", 0) == 0 && a[2] != '-') out.push_back("--jobs=" + a.substr(2));
    else out.push_back(a);
  }
  return out;
}

void only(const Args& args, const std::string& verb, std::initializer_list<const char*> allowed) {
  for (const auto& s : kSpecs) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || s.name == a;
    if (!ok && (s.takes_value ? args.get(s.name).has_value() : args.flag(s.name)))
      throw UsageError("--" + s.name + " does not apply to sweep " + verb);
  }
}

}  // namespace

int cmd_sweep(const std::vector<std::string>& argv) {
  const Args args(expand_short_jobs(argv), kSpecs);
  if (args.help() || args.positionals().empty()) {
    std::cout << usage("sweep", "plan|slurm|local|status|report|cell ...", kSummary, kSpecs);
    return args.help() ? 0 : 2;
  }
  const std::vector<std::string>& pos = args.positionals();
  const std::string verb = pos[0];
  auto need = [&](size_t n, const std::string& what) {
    if (pos.size() != n + 1) throw UsageError("sweep " + verb + ": expected " + what);
  };
  if (verb == "plan") {
    need(1, "SPEC.json --out SWEEP");
    only(args, verb, {"out"});
    const fs::path out = args.require("out");
    sweep::Manifest m = sweep::plan(pos[1], out, fs::read_symlink("/proc/self/exe"));
    if (fs::exists(out / "manifest.json")) {
      const sweep::Manifest old = sweep::read_manifest(out);
      if (sweep::to_json(old).at("cells") != sweep::to_json(m).at("cells"))
        throw UsageError((out / "manifest.json").string() +
                                    ": the sweep folder holds another plan (other cells); plan into a new --out, or remove it");
    }
    sweep::write_manifest(m);
    std::cout << "planned " << m.cells.size() << " cells (" << m.stage_cells("train").size() << " train, "
              << m.stage_cells("stylize").size() << " stylize, " << m.stage_cells("bench").size() << " bench) in "
              << (m.root / "manifest.json").string() << "\n";
    return 0;
  }
  if (verb == "cell") {
    need(2, "SWEEP ID");
    only(args, verb, {});
    return sweep::run_cell(sweep::read_manifest(pos[1]), pos[2]);
  }
  need(1, "SWEEP (a folder written by style4d sweep plan)");
  const sweep::Manifest m = sweep::read_manifest(pos[1]);
  if (verb == "local") {
    only(args, verb, {"jobs"});
    return sweep::run_local(m, parse_number<int>("jobs", args.get_or("jobs", "1"))) == 0 ? 0 : 1;
  }
  if (verb == "slurm") {
    only(args, verb, {"dry-run", "sbatch"});
    sweep::submit_slurm(m, {args.flag("dry-run"), args.get_or("sbatch", "sbatch")});
    return 0;
  }
  if (verb == "status") {
    only(args, verb, {"json"});
    sweep::print_status(m, args.flag("json"));
    return 0;
  }
  if (verb == "report") {
    only(args, verb, {"out"});
    sweep::write_report(m, args.get_or("out", (m.root / "report").string()));
    return 0;
  }
  throw UsageError("unknown sweep command '" + verb + "' (plan, slurm, local, status, report, cell)");
}

}  // namespace s4d::cli
