// style4d sweep: planning a spec into cells, the local back end (a failed cell records its error and
// the others go on; a second run skips what is done; the merged table), and the Slurm back end on a
// real single-node cluster (slurm_cluster.sh): job arrays with dependencies, one task killed while it
// trains and its cell resumed from its checkpoint on resubmission, and the same merged table as the
// local back end, byte for byte (LP_NUM_THREADS=1 in the spec fixes lavapipe's float atomics).
// The sweep: 3 scenes (two from style4d synth, 48x36, and one broken dataset) x 2 styles x 2 methods
// of the weight-free stylizer, a few iterations each.
#include <doctest/doctest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "../cli/cli_run.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;
using nlohmann::json;

struct Fixture {
  fs::path root, spec;
};

// The datasets, the second style and the spec, once per process.
const Fixture& fixture() {
  static const Fixture f = [] {
    const fs::path root = test::fresh_dir("sweep");
    REQUIRE(test::run_style4d("synth", "--out " + (root / "data/a").string() + " --cams 4 --frames 4 --size 48x36", root / "synth_a.log") == 0);
    REQUIRE(test::run_style4d("synth", "--out " + (root / "data/b").string() + " --cams 4 --frames 3 --size 48x36 --seed 1",
                              root / "synth_b.log") == 0);
    REQUIRE(test::run_style4d("make-style", "--out " + (root / "swirl.png").string() + " --size 96 --seed 7", root / "style.log") == 0);
    fs::create_directories(root / "data/broken");
    std::ofstream(root / "data/broken/poses_bounds.npy") << "not a numpy file";
    const json spec = {
        {"name", "tiny"},
        {"datasets", {{{"name", "a"}, {"path", "data/a"}, {"layout", "dynerf"}},
                      {{"name", "b"}, {"path", "data/b"}, {"downscale", 1}},
                      {{"name", "broken"}, {"path", "data/broken"}}}},
        {"presets", {"fast"}},
        {"train", {{"iters", 20}, {"fine_iters", 20}, {"args", {"--batch", "1"}}}},
        {"styles", {{{"name", "builtin"}, {"image", std::string(S4D_SOURCE_DIR) + "/assets/styles/builtin.png"}},
                    {{"name", "swirl"}, {"image", "swirl.png"}}}},
        {"methods", {{{"name", "full"}, {"stylizer", "patch"}, {"method", "full"}, {"args", {"--mlp-iters", "5"}}},
                     {{"name", "colors"}, {"stylizer", "patch"}, {"method", "colors"}, {"args", {"--mlp-iters", "0"}}}}},
        {"stylize", {{"args", {"--iters", "20", "--spiral-frames", "4"}}}},
        {"bench", {{"args", {"--spiral-frames", "4"}}}},
        {"env", {{"LP_NUM_THREADS", "1"}}},
        {"slurm", {{"default", {{"time", "00:10:00"}, {"cpus_per_task", 1}}}, {"train", {{"time", "00:05:00"}}}}}};
    std::ofstream(root / "spec.json") << spec.dump(2);
    return Fixture{root, root / "spec.json"};
  }();
  return f;
}

json read_json(const fs::path& p) { return json::parse(test::read_text(p)); }

json cell_state(const fs::path& sweep, const std::string& id) {
  const fs::path f = sweep / "cells" / id / "state.json";
  return fs::exists(f) ? read_json(f) : json(nullptr);
}

const char* const kGood[] = {"a", "b"};
const char* const kStyles[] = {"builtin", "swirl"};
const char* const kMethods[] = {"full", "colors"};

// The local back end's sweep, once per process: its folder.
const fs::path& local_sweep() {
  static const fs::path sweep = [] {
    const Fixture& f = fixture();
    const fs::path dir = f.root / "local", log = f.root / "local.log";
    REQUIRE(test::run_style4d("sweep", "plan " + f.spec.string() + " --out " + dir.string(), log) == 0);
    const auto start = std::chrono::steady_clock::now();
    // Not every cell finishes (the broken scene), so the exit status is 1.
    CHECK(test::run_style4d("sweep", "local " + dir.string() + " -j 2", log) == 256);
    MESSAGE("sweep local -j 2: " << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
    INFO(test::read_text(log));
    REQUIRE(test::run_style4d("sweep", "report " + dir.string(), f.root / "local_report.log") == 0);
    return dir;
  }();
  return sweep;
}

}  // namespace

TEST_CASE("sweep plan expands a spec into cells with their commands and dependencies; a bad spec names its field") {
  const Fixture& f = fixture();
  const fs::path sweep = f.root / "planned", log = f.root / "plan.log";
  REQUIRE_MESSAGE(test::run_style4d("sweep", "plan " + f.spec.string() + " --out " + sweep.string(), log) == 0, test::read_text(log));
  CHECK(test::read_text(log).find("planned 27 cells (3 train, 12 stylize, 12 bench)") != std::string::npos);
  const json m = read_json(sweep / "manifest.json");
  CHECK(m.at("format") == "style4d-sweep/1");
  CHECK(m.at("env").at("LP_NUM_THREADS") == "1");
  std::map<std::string, json> cells;
  for (const json& c : m.at("cells")) cells[c.at("id").get<std::string>()] = c;
  REQUIRE(cells.size() == 27);
  const json& train = cells.at("train.a.fast");
  const std::vector<std::string> cmd = train.at("command");
  CHECK(cmd[0] == "train");
  CHECK(std::find(cmd.begin(), cmd.end(), "--fine-iters") != cmd.end());
  CHECK(train.at("resume").at("command") == json({"train", "--run", (sweep / "runs/a.fast").string()}));
  const json& stylize = cells.at("stylize.a.fast.swirl.full");
  CHECK(stylize.at("after") == json({"train.a.fast"}));
  CHECK(stylize.at("resume").at("when") == (sweep / "runs/a.fast/style/swirl.full/checkpoint.s4dckpt").string());
  const std::string scmd = stylize.at("command").dump();
  for (const std::string& part : {std::string("\"--style\",\"swirl.full\""), std::string("\"--method\",\"full\""),
                                 std::string("\"--mlp-iters\",\"5\""), (f.root / "swirl.png").string()})
    CHECK_MESSAGE(scmd.find(part) != std::string::npos, part);
  CHECK(cells.at("bench.a.fast.swirl.full").at("after") == json({"stylize.a.fast.swirl.full"}));
  CHECK(cells.at("bench.a.fast.swirl.full").at("outputs")[0] == (sweep / "bench/a.fast.swirl.full/report.json").string());
  // Planning the same spec again is a no-op; the Slurm scripts without submitting.
  CHECK(test::run_style4d("sweep", "plan " + f.spec.string() + " --out " + sweep.string(), log) == 0);
  REQUIRE_MESSAGE(test::run_style4d("sweep", "slurm " + sweep.string() + " --dry-run", log) == 0, test::read_text(log));
  CHECK(test::read_text(log).find("--dependency=afterany:<train>") != std::string::npos);
  CHECK(test::read_text(log).find("--dependency=aftercorr:<stylize>") != std::string::npos);
  const std::string train_script = test::read_text(sweep / "slurm/train.sbatch");
  for (const char* line : {"#SBATCH --array=0,1,2\n", "#SBATCH --time=00:05:00\n", "#SBATCH --cpus-per-task=1\n", "'train.broken.fast'"})
    CHECK_MESSAGE(train_script.find(line) != std::string::npos, line);
  CHECK(test::read_text(sweep / "slurm/bench.sbatch").find("#SBATCH --time=00:10:00\n") != std::string::npos);
  CHECK(test::read_text(sweep / "slurm/bench.sbatch").find("#SBATCH --array=0,1,2,3,4,5,6,7,8,9,10,11\n") != std::string::npos);

  // Refusals, each naming the spec file and the field.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"presets", "presets: 'turbo': expected fast, default or quality"},
      {"styles", "styles[0].image"},
      {"name", "name: 'a b' must be letters"},
      {"colour", "colour: unknown field"},
      {"slurm", "slurm.bench.gpu: unknown setting"},
      {"layout", "datasets[0].layout: 'dnerf' but"}};
  for (const auto& [what, expected] : bad) {
    json spec = read_json(f.spec);
    if (what == "presets") spec["presets"] = {"turbo"};
    if (what == "styles") spec["styles"][0]["image"] = "nosuch.png";
    if (what == "name") spec["name"] = "a b";
    if (what == "colour") spec["colour"] = 1;
    if (what == "slurm") spec["slurm"]["bench"] = {{"gpu", 1}};
    if (what == "layout") spec["datasets"][0]["layout"] = "dnerf";
    const fs::path file = f.root / ("bad_" + what + ".json");
    std::ofstream(file) << spec.dump();
    CHECK(test::run_style4d("sweep", "plan " + file.string() + " --out " + (f.root / "bad").string(), log) != 0);
    const std::string text = test::read_text(log);
    CHECK_MESSAGE(text.find(file.string() + ": " + expected) != std::string::npos, what << ": " << text);
  }
  CHECK(!fs::exists(f.root / "bad/manifest.json"));
}

TEST_CASE("sweep local runs every cell, records a failed one without stopping the others, skips done cells, merges the table") {
  const fs::path& sweep = local_sweep();
  for (const char* scene : kGood)
    for (const char* style : kStyles)
      for (const char* method : kMethods) {
        const std::string cell = std::string(scene) + ".fast." + style + "." + method;
        CHECK_MESSAGE(cell_state(sweep, "bench." + cell).value("state", "") == "done", cell);
        CHECK(fs::exists(sweep / "bench" / cell / "report.json"));
      }
  // The broken dataset: its training failed with the reason, what follows it never started.
  const json broken = cell_state(sweep, "train.broken.fast");
  CHECK(broken.at("state") == "failed");
  CHECK(broken.at("error").get<std::string>().find("style4d train: error:") != std::string::npos);
  CHECK(cell_state(sweep, "stylize.broken.fast.builtin.full").is_null());
  // A second run skips every done cell and tries the failed one again.
  const fs::path log = sweep.parent_path() / "local_again.log";
  CHECK(test::run_style4d("sweep", "local " + sweep.string(), log) != 0);
  CHECK(cell_state(sweep, "train.a.fast").at("attempts") == 1);
  CHECK(cell_state(sweep, "train.broken.fast").at("attempts") == 2);
  CHECK(test::run_style4d("sweep", "status " + sweep.string(), log) == 0);
  const std::string status = test::read_text(log);
  CHECK(status.find("18 done, 1 failed, 8 not started") != std::string::npos);

  // The table: scene x method rows, the 12 metric columns, best per scene in bold, the missing cells.
  const std::string md = test::read_text(sweep / "report/report.md");
  CHECK(md.find("| scene | method | styles | UIQM ↑ |") != std::string::npos);
  CHECK(md.find("| Content LPIPS ↓ |\n") != std::string::npos);
  CHECK(md.find("Gram") == std::string::npos);
  for (const char* row : {"| a | full | 2/2 |", "| a | colors | 2/2 |", "| b | full | 2/2 |", "| broken | colors | 0/2 |"})
    CHECK_MESSAGE(md.find(row) != std::string::npos, row);
  CHECK(md.find("**") != std::string::npos);
  CHECK(md.find("- `bench.broken.fast.swirl.colors`: not started") != std::string::npos);
  const json report = read_json(sweep / "report/report.json");
  REQUIRE(report.at("rows").size() == 6);
  CHECK(report.at("results").size() == 8);
  CHECK(report.at("missing").size() == 4);
  // Each row the mean of its styles' cells; the bold one the best of its scene.
  const json& row = report.at("rows")[0];
  double mean = 0;
  for (const json& r : report.at("results"))
    if (r.at("scene") == "a" && r.at("method") == "full") mean += r.at("content_ssim").get<double>() / 2;
  CHECK(row.at("content_ssim").get<double>() == doctest::Approx(mean).epsilon(1e-12));
  const double ssim_full = report.at("rows")[0].at("content_ssim"), ssim_colors = report.at("rows")[1].at("content_ssim");
  const std::string best = "**" + [](double v) { std::ostringstream s; s.precision(4); s << std::fixed << v; return s.str(); }(std::max(ssim_full, ssim_colors)) + "**";
  CHECK(md.find(best) != std::string::npos);
  const std::string csv = test::read_text(sweep / "report/report.csv");
  CHECK(csv.rfind("scene,method,styles,uiqm,", 0) == 0);
  CHECK(test::read_text(sweep / "report/results.csv").find("bench.b.fast.swirl.colors,b,colors,swirl,") != std::string::npos);
  for (const char* plot : {"uiqm.png", "warp_loss.png", "content_ssim.png"}) CHECK_MESSAGE(fs::exists(sweep / "report/plots" / plot), plot);
}

TEST_CASE("sweep slurm on a single-node Slurm: job arrays, a killed task resumes on resubmission, the local back end's table") {
  const char* ci = std::getenv("CI");
  const bool in_ci = ci != nullptr && std::string(ci) == "true";
  const fs::path script = fs::path(S4D_SOURCE_DIR) / "tests/sweep/slurm_cluster.sh";
  const fs::path cluster = test::fresh_dir("sweep_slurm_cluster");
  const fs::path cluster_log = cluster.parent_path() / (cluster.filename().string() + ".log");
  const int started = std::system(("bash " + script.string() + " start " + cluster.string() + " > " + cluster_log.string() + " 2>&1").c_str());
  if (started != 0) {
    const std::string why = "cannot start a single-node Slurm cluster: " + test::read_text(cluster_log);
    if (in_ci) FAIL(why);
    MESSAGE("SKIPPED (outside CI): " << why);
    std::exit(77);
  }
  struct Stop {
    std::string command;
    ~Stop() { (void)std::system(command.c_str()); }
  } stop{"bash " + script.string() + " stop " + cluster.string() + " >> " + cluster_log.string() + " 2>&1"};
  setenv("SLURM_CONF", (cluster / "slurm.conf").c_str(), 1);

  const fs::path& local = local_sweep();
  const Fixture& f = fixture();
  const fs::path sweep = f.root / "slurm", log = f.root / "slurm.log";
  auto shell = [&](const std::string& cmd) {
    const std::string out_file = (f.root / "shell.out").string();
    const int rc = std::system(("timeout 30 " + cmd + " > " + out_file + " 2>&1").c_str());
    return std::make_pair(rc, test::read_text(out_file));
  };
  // Waits until the cluster has no pending or running job, at most `seconds`.
  auto wait_idle = [&](int seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (std::chrono::steady_clock::now() < end) {
      const auto [rc, out] = shell("squeue -h -o '%i %T'");
      if (rc == 0 && out.empty()) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    (void)test::run_style4d("sweep", "status " + sweep.string(), log);
    FAIL("the sweep's jobs did not finish in " << seconds << " s; squeue: " << shell("squeue").second << "\nstatus:\n" << test::read_text(log));
  };
  REQUIRE(test::run_style4d("sweep", "plan " + f.spec.string() + " --out " + sweep.string(), log) == 0);
  const auto start = std::chrono::steady_clock::now();
  REQUIRE_MESSAGE(test::run_style4d("sweep", "slurm " + sweep.string(), log) == 0, test::read_text(log));
  const std::string submitted = test::read_text(log);
  CHECK(submitted.find("train: job ") != std::string::npos);
  CHECK(submitted.find("bench: job ") != std::string::npos);

  // Kill one stylize task while it trains (stage 4 under way): SIGTERM makes the cell write its
  // checkpoint. If the task finished first, another one is tried.
  std::string killed;
  std::set<std::string> tried;
  const auto kill_end = std::chrono::steady_clock::now() + std::chrono::seconds(180);
  while (killed.empty() && std::chrono::steady_clock::now() < kill_end) {
    for (const char* scene : kGood)
      for (const char* style : kStyles) {
        const std::string id = std::string("stylize.") + scene + ".fast." + style + ".full";
        const json s = cell_state(sweep, id);
        if (!killed.empty() || tried.count(id) || s.is_null() || s.value("state", "") != "running" || !s.contains("slurm_job")) continue;
        if (test::read_text(sweep / "cells" / id / "log.txt").find("[stage 4") == std::string::npos) continue;
        tried.insert(id);
        const auto [rc, out] = shell("scancel " + s.at("slurm_job").get<std::string>());
        REQUIRE_MESSAGE(rc == 0, out);
        for (int i = 0; i < 120 && cell_state(sweep, id).value("state", "") == "running"; ++i)
          std::this_thread::sleep_for(std::chrono::milliseconds(500));
        if (cell_state(sweep, id).value("state", "") == "interrupted") killed = id;
      }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  REQUIRE_MESSAGE(!killed.empty(), "no stylize task could be killed during stage 4 (tried " << tried.size() << ")");
  wait_idle(300);
  const std::string bench_of_killed = "bench." + killed.substr(std::string("stylize.").size());
  CHECK(cell_state(sweep, killed).at("state") == "interrupted");
  CHECK(cell_state(sweep, killed).at("error").get<std::string>().find("checkpoint") != std::string::npos);
  CHECK(cell_state(sweep, bench_of_killed).is_null());  // cancelled with its dependency
  CHECK(test::run_style4d("sweep", "status " + sweep.string() + " --json", log) == 0);
  const json status = json::parse(test::read_text(log));
  for (const json& c : status.at("cells")) {
    if (c.at("id") == "train.a.fast") CHECK(c.value("slurm_state", "") == "COMPLETED");
    if (c.at("id") == "train.broken.fast") CHECK(c.value("slurm_state", "") == "FAILED");
    if (c.at("id") == killed) CHECK(c.value("slurm_state", "") == "CANCELLED");
  }

  // Resubmission: only what is not done; the killed cell continues from its checkpoint.
  REQUIRE_MESSAGE(test::run_style4d("sweep", "slurm " + sweep.string(), log) == 0, test::read_text(log));
  CHECK(test::read_text(log).find("stylize: job ") != std::string::npos);
  wait_idle(300);
  MESSAGE("sweep on Slurm, kill and resubmission: " << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
  const json resumed = cell_state(sweep, killed);
  CHECK(resumed.at("state") == "done");
  CHECK(resumed.at("attempts") == 2);
  CHECK(resumed.at("resumed") == true);
  const std::string cell_log = test::read_text(sweep / "cells" / killed / "log.txt");
  CHECK(cell_log.find("stage 4: interrupted at iteration") != std::string::npos);
  CHECK(cell_log.find("(resumed from " + (sweep / "runs").string()) != std::string::npos);
  CHECK(cell_state(sweep, "train.a.fast").at("attempts") == 1);
  CHECK(cell_state(sweep, bench_of_killed).at("state") == "done");
  CHECK(!fs::is_empty(sweep / "slurm/logs"));

  // The same table as the local back end, byte for byte.
  REQUIRE(test::run_style4d("sweep", "report " + sweep.string(), log) == 0);
  for (const char* file : {"report.md", "report.csv", "results.csv"})
    CHECK_MESSAGE(test::read_text(sweep / "report" / file) == test::read_text(local / "report" / file), file);
  CHECK(read_json(sweep / "report/report.json").at("rows") == read_json(local / "report/report.json").at("rows"));
}
