#include "s4d/study/study_server.h"

#include <httplib.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>
#include <thread>

#include "s4d/study/study_file.h"
#include "s4d/study/study_report.h"
#include "s4d/study/vote_store.h"
#include "s4d/util/atomic_file.h"

namespace s4d::study {

extern const char* const kStudyPage;  // study_page.html, embedded at build time

namespace {

namespace fs = std::filesystem;

constexpr size_t kMaxVoteBytes = 4096;        // a vote is about 150 bytes
constexpr size_t kMaxRequestBytes = 64 * 1024;  // httplib refuses larger bodies before reading them
constexpr size_t kThreads = 48;
constexpr int64_t kClockSlackMs = 60 * 1000;
constexpr int64_t kMaxShownAgeMs = 7LL * 24 * 3600 * 1000;

int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void reply(httplib::Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void refuse(httplib::Response& res, int status, const std::string& why) { reply(res, status, {{"error", why}}); }

std::string random_token() {
  std::random_device rd;  // /dev/urandom
  static const char kHex[] = "0123456789abcdef";
  std::string t;
  for (int k = 0; k < 32; ++k) t += kHex[rd() % 16];
  return t;
}

// The page's view of a participant: their pairs in order with sides resolved, no method names.
nlohmann::json participant_json(const Study& s, const Participant& p, const std::vector<Vote>& votes) {
  nlohmann::json items = nlohmann::json::array();
  for (const Placement& o : p.order) {
    const Item& it = s.item(o.item);
    nlohmann::json criteria = nlohmann::json::array(), answers = nlohmann::json::object();
    for (const Criterion& c : it.criteria()) criteria.push_back({{"id", c.id}, {"question", c.question}});
    for (const Vote& v : votes)
      if (v.item == it.id) answers[v.criterion] = v.choice;
    items.push_back({{"id", it.id}, {"part", it.part}, {"kind", it.kind}, {"left", "/" + it.media[o.swap ? 1 : 0]},
                     {"right", "/" + it.media[o.swap ? 0 : 1]},
                     {"style_image", it.style_image.empty() ? "" : "/" + it.style_image}, {"criteria", criteria},
                     {"answers", answers}});
  }
  nlohmann::json parts = nlohmann::json::array();
  for (const Part& part : s.parts) parts.push_back({{"id", part.id}, {"title", part.title}});
  return {{"code", p.code}, {"fps", s.fps}, {"parts", parts}, {"items", items}};
}

// Checks a posted vote against the study and the participant; on success fills `vote`, else says
// why with the HTTP status to send.
bool parse_vote(const Study& s, const std::string& body, Vote& vote, int& status, std::string& why) {
  status = 400;
  if (body.size() > kMaxVoteBytes) {
    status = 413;
    why = "request body is " + std::to_string(body.size()) + " bytes; a vote is at most " + std::to_string(kMaxVoteBytes);
    return false;
  }
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(body);
  } catch (const nlohmann::json::exception& e) {
    why = std::string("malformed JSON: ") + e.what();
    return false;
  }
  if (!j.is_object()) return why = "expected a JSON object", false;
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "code" && it.key() != "item" && it.key() != "criterion" && it.key() != "choice" && it.key() != "shown_ms")
      return why = "unknown field '" + it.key() + "'", false;
  for (const char* f : {"code", "item", "criterion", "choice"})
    if (!j.contains(f) || !j.at(f).is_string()) return why = std::string(f) + ": missing or not a string", false;
  if (!j.contains("shown_ms") || !j.at("shown_ms").is_number_integer()) return why = "shown_ms: missing or not an integer", false;
  vote.participant = j.at("code");
  vote.item = j.at("item");
  vote.criterion = j.at("criterion");
  vote.choice = j.at("choice");
  vote.shown_ms = j.at("shown_ms");
  vote.answered_ms = now_ms();
  const Participant* p = s.participant(vote.participant);
  if (!p) return status = 403, why = "unknown participant code", false;
  const Placement* placed = nullptr;
  for (const Placement& o : p->order)
    if (o.item == vote.item) placed = &o;
  if (!placed) return status = 404, why = "item '" + vote.item + "' is not one of this participant's pairs", false;
  const Item& it = s.item(vote.item);
  bool known = false;
  for (const Criterion& c : it.criteria()) known = known || c.id == vote.criterion;
  if (!known) return why = "criterion '" + vote.criterion + "' is not asked of item " + it.id, false;
  if (vote.choice != "left" && vote.choice != "right" && vote.choice != "same")
    return why = "choice: expected left, right or same, got '" + vote.choice + "'", false;
  if (vote.shown_ms > vote.answered_ms + kClockSlackMs || vote.shown_ms < vote.answered_ms - kMaxShownAgeMs)
    return why = "shown_ms: " + std::to_string(vote.shown_ms) + " is not a time in the last week (the server's clock says " +
                 std::to_string(vote.answered_ms) + ")", false;
  vote.swap = placed->swap;
  const int left = placed->swap ? 1 : 0;
  vote.chosen = vote.choice == "same" ? "same" : it.methods[vote.choice == "left" ? left : 1 - left];
  return true;
}

bool admin(const httplib::Request& req, httplib::Response& res, const std::string& token) {
  std::string given = req.get_param_value("token");
  const std::string auth = req.get_header_value("Authorization");
  if (given.empty() && auth.rfind("Bearer ", 0) == 0) given = auth.substr(7);
  // Compared in full whatever the first difference, so timing does not reveal the token.
  unsigned diff = given.size() != token.size();
  for (size_t k = 0; k < token.size(); ++k) diff |= static_cast<unsigned>(k < given.size() ? given[k] ^ token[k] : 1);
  if (diff == 0) return true;
  refuse(res, 403, "the results need the admin token (?token=... or Authorization: Bearer ...), printed when the server started");
  return false;
}

}  // namespace

void serve_study(const ServeOptions& o, const std::atomic<bool>& stop, const std::function<void(int, const std::string&)>& on_ready) {
  const Study study = read_study(o.study);
  VoteStore store(o.study / "votes.sqlite");
  std::string token = o.admin_token;
  if (token.empty()) {
    token = random_token();
    util::write_file_atomic(o.study / "admin_token", token + "\n");
    fs::permissions(o.study / "admin_token", fs::perms::owner_read | fs::perms::owner_write);
  }

  httplib::Server server;
  // A participant's page holds a connection open between votes (keep-alive): threads for a full lab
  // at once, and idle connections let go after 2 s.
  server.new_task_queue = [] { return new httplib::ThreadPool(kThreads); };
  server.set_keep_alive_timeout(2);
  server.set_payload_max_length(kMaxRequestBytes);
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler's own refusal
    if (res.status == 413) refuse(res, 413, "request body over " + std::to_string(kMaxRequestBytes) + " bytes");
    else if (res.status == 404) refuse(res, 404, "no such page");
    else refuse(res, res.status, "request refused");
  });
  server.Get("/", [](const httplib::Request&, httplib::Response& res) { res.set_content(kStudyPage, "text/html; charset=utf-8"); });
  // Browsers ask for an icon; "none" keeps their consoles free of 404s.
  server.Get("/favicon.ico", [](const httplib::Request&, httplib::Response& res) { res.status = 204; });
  if (!server.set_mount_point("/media", (o.study / "media").string()))
    throw std::runtime_error((o.study / "media").string() + ": missing (the study's videos and frames; `style4d study plan` writes them)");
  server.set_file_extension_and_mimetype_mapping("webm", "video/webm");
  server.Get(R"(/api/participant/([A-Za-z0-9]{1,64}))", [&](const httplib::Request& req, httplib::Response& res) {
    const Participant* p = study.participant(req.matches[1]);
    if (!p) return refuse(res, 404, "unknown participant code");
    reply(res, 200, participant_json(study, *p, store.of_participant(p->code)));
  });
  server.Post("/api/vote", [&](const httplib::Request& req, httplib::Response& res) {
    Vote v;
    int status = 400;
    std::string why;
    if (!parse_vote(study, req.body, v, status, why)) return refuse(res, status, why);
    if (store.add(v) == AddResult::duplicate)
      return refuse(res, 409, "already answered: " + v.participant + ", " + v.item + ", " + v.criterion + " (a vote is final)");
    reply(res, 201, {{"stored", true}});
  });
  server.Get("/admin/results", [&](const httplib::Request& req, httplib::Response& res) {
    if (admin(req, res, token)) reply(res, 200, study_report_json(study, store.all()));
  });
  server.Get("/admin/votes", [&](const httplib::Request& req, httplib::Response& res) {
    if (!admin(req, res, token)) return;
    nlohmann::json rows = nlohmann::json::array();
    for (const Vote& v : store.all())
      rows.push_back({{"participant", v.participant}, {"item", v.item}, {"criterion", v.criterion}, {"choice", v.choice},
                      {"chosen", v.chosen}, {"swap", v.swap}, {"shown_ms", v.shown_ms}, {"answered_ms", v.answered_ms}});
    reply(res, 200, rows);
  });

  const int port = o.port == 0 ? server.bind_to_any_port(o.host) : (server.bind_to_port(o.host, o.port) ? o.port : -1);
  if (port <= 0) throw std::runtime_error("cannot listen on " + o.host + ":" + std::to_string(o.port) + " (in use, or no such address)");
  std::atomic<bool> ended{false};
  std::thread watcher([&] {
    while (!stop && !ended && !server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!stop && !ended) on_ready(port, token);
    while (!stop && !ended) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    server.stop();
  });
  server.listen_after_bind();
  ended = true;
  watcher.join();
}

}  // namespace s4d::study
