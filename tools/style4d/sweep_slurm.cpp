// style4d sweep slurm / status: the sweep as sbatch job arrays (one per stage, one task per cell)
// and what Slurm (sacct, else squeue) and the cells' own files say about them.
//
// Dependencies: stylize after train with afterany (each stylize cell checks that its own train cell
// is done, so one scene's failed training does not hold back the others' stylize cells, as afterok
// on the whole array would); bench after stylize with aftercorr (task i after task i: the two arrays
// hold the same indices, a done stylize cell is included and skips at once) and
// --kill-on-invalid-dep, so the bench of a failed stylize cell is cancelled rather than left pending.
#include <sys/wait.h>

#include <cstdio>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>

#include "s4d/util/atomic_file.h"
#include "sweep.h"

namespace s4d::cli::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

// Runs a shell command line; returns its exit status and its output (stdout and stderr).
int capture(const std::string& command, std::string& output) {
  output.clear();
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) output.append(buf, n);
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void add_index(std::string& list, size_t i) {
  if (!list.empty()) list += ',';
  list += std::to_string(i);
}

fs::path jobs_file(const Manifest& m) { return m.root / "slurm" / "jobs.json"; }

json read_jobs(const Manifest& m) {
  std::ifstream in(jobs_file(m));
  if (!in) return {{"submissions", json::array()}};
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw std::runtime_error(jobs_file(m).string() + ": not valid JSON (" + e.what() + ")");
  }
}

std::string script(const Manifest& m, const std::string& stage, const std::vector<const Cell*>& cells, const std::string& indices) {
  const SlurmStage& s = m.slurm.at(stage);
  std::ostringstream o;
  o << "#!/bin/bash\n# " << stage << " cells of the sweep " << m.name << " (style4d sweep slurm " << m.root.string() << ")\n"
    << "#SBATCH --job-name=s4d-" << m.name << "-" << stage << "\n"
    << "#SBATCH --array=" << indices;
  if (s.max_parallel > 0) o << "%" << s.max_parallel;
  o << "\n"
    << "#SBATCH --output=" << (m.root / "slurm" / "logs" / (stage + "_%a_%A.log")).string() << "\n"
    << "#SBATCH --chdir=" << m.root.string() << "\n"
    << "#SBATCH --time=" << s.time << "\n"
    << "#SBATCH --cpus-per-task=" << s.cpus_per_task << "\n"
    << "#SBATCH --kill-on-invalid-dep=yes\n";
  if (s.gpus > 0) o << "#SBATCH --gres=gpu:" << s.gpus << "\n";
  if (!s.mem.empty()) o << "#SBATCH --mem=" << s.mem << "\n";
  if (!s.partition.empty()) o << "#SBATCH --partition=" << s.partition << "\n";
  if (!s.account.empty()) o << "#SBATCH --account=" << s.account << "\n";
  for (const std::string& e : s.extra) o << "#SBATCH " << e << "\n";
  o << "# array index -> cell (the stage's cells in manifest order)\ncells=(";
  for (const Cell* c : cells) o << "\n  " << quoted(c->id);
  o << "\n)\nexec " << quoted(m.program.string()) << " sweep cell " << quoted(m.root.string()) << " \"${cells[$SLURM_ARRAY_TASK_ID]}\"\n";
  return o.str();
}

// "123_4" keys from sacct/squeue lines "123_4|STATE" (also "123_[1-3,5]|PENDING", a pending range).
void parse_states(const std::string& text, std::map<std::string, std::string>& out) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const size_t bar = line.find('|'), under = line.find('_');
    if (bar == std::string::npos || under == std::string::npos || under > bar) continue;
    const std::string job = line.substr(0, under), tasks = line.substr(under + 1, bar - under - 1);
    std::string state = line.substr(bar + 1);
    if (const size_t sp = state.find(' '); sp != std::string::npos) state.resize(sp);  // "CANCELLED by 0"
    if (tasks.empty() || tasks[0] != '[') {
      out[job + "_" + tasks] = state;
      continue;
    }
    std::istringstream ranges(tasks.substr(1, tasks.find_first_of("]%") - 1));
    std::string r;
    while (std::getline(ranges, r, ',')) {
      const size_t dash = r.find('-');
      try {
        const int a = std::stoi(r.substr(0, dash)), b = dash == std::string::npos ? a : std::stoi(r.substr(dash + 1));
        for (int i = a; i <= b; ++i) out[job + "_" + std::to_string(i)] = state;
      } catch (const std::exception&) {
      }
    }
  }
}

std::string job_list(const std::map<std::string, std::string>& ids) {
  std::set<std::string> jobs;
  for (const auto& [cell, id] : ids) jobs.insert(id.substr(0, id.find('_')));
  std::string list;
  for (const std::string& j : jobs) list += (list.empty() ? "" : ",") + j;
  return list;
}

}  // namespace

std::map<std::string, std::string> slurm_job_ids(const Manifest& m) {
  std::map<std::string, std::string> ids;
  const json jobs = read_jobs(m);  // (a temporary's member in the range-for would dangle)
  for (const json& sub : jobs.at("submissions"))
    for (const auto& [stage, s] : sub.at("stages").items())
      for (const auto& [index, cell] : s.at("cells").items()) ids[cell.get<std::string>()] = s.at("job").get<std::string>() + "_" + index;
  return ids;
}

std::map<std::string, std::string> slurm_states(const Manifest& m) {
  const std::map<std::string, std::string> ids = slurm_job_ids(m);
  std::map<std::string, std::string> by_task, out;
  if (ids.empty()) return out;
  std::string text;
  const std::string jobs = job_list(ids);
  if (capture("sacct -n -P -X -j " + jobs + " --format=JobID,State", text) == 0) parse_states(text, by_task);
  // Without accounting storage sacct knows nothing: squeue still knows what is pending or running.
  if (by_task.empty() && capture("squeue -h -r -t all -j " + jobs + " -o '%i|%T'", text) == 0) parse_states(text, by_task);
  for (const auto& [cell, id] : ids)
    if (auto it = by_task.find(id); it != by_task.end()) out[cell] = it->second;
  return out;
}

int submit_slurm(const Manifest& m, const SlurmOptions& options) {
  if (!options.dry_run) {
    for (const auto& [cell, state] : slurm_states(m))
      if (state == "PENDING" || state == "RUNNING" || state == "REQUEUED" || state == "SUSPENDED" || state == "CONFIGURING")
        throw std::runtime_error("job " + slurm_job_ids(m).at(cell) + " (" + cell + ") of this sweep is still " + state +
                                 "; wait for it (style4d sweep status " + m.root.string() + ") or scancel it first");
  }
  const std::vector<const Cell*> trains = m.stage_cells("train"), stylizes = m.stage_cells("stylize"), benches = m.stage_cells("bench");
  if (stylizes.size() != benches.size()) throw std::runtime_error("manifest: the stylize and bench cells must pair up one to one");
  std::map<std::string, std::string> indices;  // stage -> "0,2,5"
  for (size_t i = 0; i < trains.size(); ++i)
    if (!cell_done(m, *trains[i])) add_index(indices["train"], i);
  for (size_t i = 0; i < stylizes.size(); ++i) {
    if (benches[i]->after != std::vector<std::string>{stylizes[i]->id})
      throw std::runtime_error("manifest: bench cell " + benches[i]->id + " must follow stylize cell " + stylizes[i]->id);
    if (cell_done(m, *stylizes[i]) && cell_done(m, *benches[i])) continue;
    for (const char* stage : {"stylize", "bench"}) add_index(indices[stage], i);
  }
  if (indices.empty()) {
    std::cerr << "sweep: every cell is done; nothing to submit\n";
    return 0;
  }
  fs::create_directories(m.root / "slurm" / "logs");
  json submission = {{"time", static_cast<long long>(std::time(nullptr))}, {"stages", json::object()}};
  std::string previous;  // the job id of the stage before
  int submitted = 0;
  for (const char* stage : kStages) {
    if (!indices.count(stage)) {
      previous.clear();
      continue;
    }
    const std::vector<const Cell*>& cells = std::string(stage) == "train" ? trains : std::string(stage) == "stylize" ? stylizes : benches;
    const fs::path file = m.root / "slurm" / (std::string(stage) + ".sbatch");
    util::write_file_atomic(file, script(m, stage, cells, indices[stage]));
    std::string command = options.sbatch + " --parsable";
    if (!previous.empty()) command += std::string(" --dependency=") + (std::string(stage) == "bench" ? "aftercorr:" : "afterany:") + previous;
    command.append(" ").append(quoted(file.string()));
    if (options.dry_run) {
      std::cout << stage << ": " << command << "\n";
      previous = std::string("<") + stage + ">";
      continue;
    }
    std::string out;
    if (capture(command, out) != 0) throw std::runtime_error(std::string(stage) + ": sbatch failed: " + out);
    std::string job = out.substr(0, out.find_first_of(";\n"));
    if (job.empty() || job.find_first_not_of("0123456789") != std::string::npos)
      throw std::runtime_error(std::string(stage) + ": sbatch printed '" + out + "', not a job id");
    json task_cells = json::object();
    std::istringstream list(indices[stage]);
    for (std::string i; std::getline(list, i, ',');) task_cells[i] = cells[std::stoul(i)]->id;
    submission["stages"][stage] = {{"job", job}, {"array", indices[stage]}, {"cells", task_cells}};
    std::cout << stage << ": job " << job << " (array " << indices[stage] << ")\n";
    previous = job;
    ++submitted;
  }
  if (!options.dry_run) {
    json jobs = read_jobs(m);
    jobs["submissions"].push_back(submission);
    util::write_file_atomic(jobs_file(m), jobs.dump(2) + "\n");
  }
  return submitted;
}

int print_status(const Manifest& m, bool as_json) {
  const std::map<std::string, std::string> ids = slurm_job_ids(m), states = slurm_states(m);
  json cells = json::array();
  std::map<std::string, int> counts;
  for (const Cell& c : m.cells) {
    const json s = read_state(m, c.id);
    json row = {{"id", c.id}, {"stage", c.stage}, {"state", cell_state(m, c)}, {"attempts", s.is_null() ? 0 : s.value("attempts", 0)}};
    if (!s.is_null() && s.contains("error") && row["state"] != "done") row["error"] = s["error"];
    if (auto it = ids.find(c.id); it != ids.end()) row["slurm_job"] = it->second;
    if (auto it = states.find(c.id); it != states.end()) row["slurm_state"] = it->second;
    ++counts[row["state"].get<std::string>()];
    cells.push_back(row);
  }
  const int done = counts.count("done") ? counts.at("done") : 0;  // not counts["done"]: that would list "done": 0
  const int not_done = static_cast<int>(m.cells.size()) - done;
  if (as_json) {
    std::cout << json{{"sweep", m.root.string()}, {"counts", counts}, {"cells", cells}}.dump(2) << "\n";
    return not_done;
  }
  size_t width = 4;
  for (const Cell& c : m.cells) width = std::max(width, c.id.size());
  std::cout << std::left << std::setw(static_cast<int>(width) + 2) << "cell" << std::setw(13) << "state" << std::setw(9) << "attempts"
            << "slurm\n";
  for (const json& r : cells) {
    std::string slurm = r.value("slurm_job", "");
    if (r.contains("slurm_state")) slurm.append(" ").append(r["slurm_state"].get<std::string>());
    std::cout << std::setw(static_cast<int>(width) + 2) << r["id"].get<std::string>() << std::setw(13) << r["state"].get<std::string>()
              << std::setw(9) << r["attempts"].get<int>() << slurm << "\n";
    if (r.contains("error")) std::cout << "    " << r["error"].get<std::string>() << "\n";
  }
  std::cout << "\n";
  std::string summary;
  for (const auto& [state, n] : counts)
    if (n > 0) summary += (summary.empty() ? "" : ", ") + std::to_string(n) + " " + state;
  std::cout << summary << "\n";
  return not_done;
}

}  // namespace s4d::cli::sweep
