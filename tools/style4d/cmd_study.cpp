// style4d study plan|serve|report: Style4D-Bench's user study (docs/study.md). The work is in
// bench/study (library s4d_study); this file parses the command line.
#include <atomic>
#include <csignal>
#include <filesystem>
#include <iostream>

#include "args.h"
#include "commands.h"
#include "s4d/study/study_plan.h"
#include "s4d/study/study_report.h"
#include "s4d/study/study_server.h"
#include "s4d/study/vote_store.h"

namespace s4d::cli {

namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int) { g_stop = true; }

const char* const kSummary =
    "Style4D-Bench's user study: pairs of stylised videos and frames judged side by side in a browser.\n\n"
    "  plan --bench DIR [--bench DIR ...] [--sweep SWEEP] --out STUDY\n"
    "        pairs of methods per scene, style and view from bench outputs (run mode: Part 1, 4D\n"
    "        stylization; frames mode: Part 2, video stylization), single frames pulled from them,\n"
    "        two attention checks, each participant's seeded order and sides; WebM videos in STUDY/media\n"
    "  serve STUDY [--host H] [--port N] [--token T]\n"
    "        the study's web page on http://127.0.0.1:8080/ (--host 0.0.0.0 for other machines); votes\n"
    "        in STUDY/votes.sqlite; results at /admin/results?token=T\n"
    "  report STUDY [--out DIR]\n"
    "        vote shares per method and criterion with 95 % Wilson intervals, Bradley-Terry scores,\n"
    "        Krippendorff's alpha; attention-check failures excluded; JSON, CSV, Markdown (default\n"
    "        STUDY/report/)";

const std::vector<OptionSpec> kSpecs = {
    {"bench", "plan: a style4d bench output folder (or its report.json); repeat for several", true, "DIR"},
    {"sweep", "plan: a sweep folder: every finished bench cell's report", true, "SWEEP"},
    {"out", "plan: the study folder to create; report: the report folder (default STUDY/report)", true, "DIR"},
    {"participants", "plan: participant codes to draw (default 20)", true, "N"},
    {"seed", "plan: seed of the codes, orders and sides (default 1)", true, "N"},
    {"fps", "plan: frame rate of the videos (default 30)", true, "FPS"},
    {"max-frames", "plan: frames per video at most (default 300, the paper's 10 s)", true, "N"},
    {"frame-pairs", "plan: single-frame pairs of Part 1 and Part 2 (default 4,6, as the paper)", true, "N1,N2"},
    {"methods", "plan: only these methods, comma-separated (default: all but original)", true, "A,B,..."},
    {"host", "serve: address to listen on (default 127.0.0.1: this machine only)", true, "HOST"},
    {"port", "serve: port (default 8080; 0: any free one, printed)", true, "N"},
    {"token", "serve: the admin token of the results pages (default: a random one, in STUDY/admin_token)", true, "T"},
};

void only(const Args& args, const std::string& verb, std::initializer_list<const char*> allowed) {
  for (const auto& s : kSpecs) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || s.name == a;
    if (!ok && args.get(s.name)) throw std::invalid_argument("--" + s.name + " does not apply to study " + verb);
  }
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  for (size_t end; (end = text.find(',', start)) != std::string::npos; start = end + 1) out.push_back(text.substr(start, end - start));
  out.push_back(text.substr(start));
  return out;
}

int plan(const Args& args) {
  only(args, "plan", {"bench", "sweep", "out", "participants", "seed", "fps", "max-frames", "frame-pairs", "methods"});
  if (args.positionals().size() != 1) throw std::invalid_argument("study plan: unexpected argument '" + args.positionals()[1] + "'");
  study::PlanOptions o;
  for (const std::string& b : args.get_all("bench")) o.reports.push_back(b);
  if (auto s = args.get("sweep"))
    for (const fs::path& r : study::sweep_reports(*s)) o.reports.push_back(r);
  o.out = args.require("out");
  if (auto v = args.get("participants")) o.participants = parse_number<int>("participants", *v);
  if (auto v = args.get("seed")) o.seed = parse_number<uint64_t>("seed", *v);
  if (auto v = args.get("fps")) {
    try {
      size_t used = 0;
      o.fps = std::stod(*v, &used);
      if (used != v->size()) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::invalid_argument("--fps: expected a number, got '" + *v + "'");
    }
  }
  if (auto v = args.get("max-frames")) o.max_frames = parse_number<int>("max-frames", *v);
  if (auto v = args.get("frame-pairs")) {
    const std::vector<std::string> n = split(*v);
    if (n.size() != 2) throw std::invalid_argument("--frame-pairs: expected N1,N2 (Part 1's and Part 2's), got '" + *v + "'");
    o.frame_pairs_4d = parse_number<int>("frame-pairs", n[0]);
    o.frame_pairs_video = parse_number<int>("frame-pairs", n[1]);
  }
  if (auto v = args.get("methods")) o.methods = split(*v);
  const study::Study s = study::plan_study(o);
  int videos = 0, frames = 0;
  for (const study::Item& it : s.items) (it.kind == "video" ? videos : frames) += it.check.empty() ? 1 : 0;
  std::cout << "study planned in " << o.out.string() << ": " << videos << " video pairs, " << frames << " frame pairs, 2 attention checks, "
            << s.participants.size() << " participant codes (study.json)\n";
  return 0;
}

int serve(const Args& args) {
  only(args, "serve", {"host", "port", "token"});
  if (args.positionals().size() != 2) throw std::invalid_argument("study serve: expected STUDY");
  study::ServeOptions o;
  o.study = args.positionals()[1];
  o.host = args.get_or("host", o.host);
  if (auto v = args.get("port")) o.port = parse_number<int>("port", *v);
  if (o.port < 0 || o.port > 65535) throw std::invalid_argument("--port: expected 0 to 65535");
  o.admin_token = args.get_or("token", "");
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  study::serve_study(o, g_stop, [&](int port, const std::string& token) {
    const std::string url = "http://" + (o.host == "0.0.0.0" ? std::string("HOSTNAME") : o.host) + ":" + std::to_string(port);
    std::cout << "serving " << o.study.string() << " at " << url << "/ (Ctrl-C stops; votes in "
              << (o.study / "votes.sqlite").string() << ")\nresults: " << url << "/admin/results?token=" << token << std::endl;
  });
  return 0;
}

int report(const Args& args) {
  only(args, "report", {"out"});
  if (args.positionals().size() != 2) throw std::invalid_argument("study report: expected STUDY");
  const fs::path dir = args.positionals()[1];
  const study::Study s = study::read_study(dir);
  const study::VoteStore store(dir / "votes.sqlite", true);
  const nlohmann::json r = study::study_report_json(s, store.all());
  const fs::path out = args.get_or("out", (dir / "report").string());
  study::write_study_report(out, r);
  const auto& p = r.at("participants");
  std::cout << (out / "study_report.md").string() << ": " << p.at("included") << " participants counted, " << p.at("excluded")
            << " excluded by the attention checks (also .json, .csv)\n";
  return 0;
}

}  // namespace

int cmd_study(const std::vector<std::string>& argv) {
  std::optional<Args> args;
  try {
    args.emplace(argv, kSpecs);
    if (args->help() || args->positionals().empty()) {
      std::cout << usage("study", "plan|serve|report ...", kSummary, kSpecs);
      return args->help() ? 0 : 2;
    }
    const std::string verb = args->positionals()[0];
    if (verb == "plan") return plan(*args);
    if (verb == "serve") return serve(*args);
    if (verb == "report") return report(*args);
    throw std::invalid_argument("unknown study command '" + verb + "' (plan, serve or report)");
  } catch (const std::invalid_argument& e) {
    std::cerr << "style4d study: error: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace s4d::cli
