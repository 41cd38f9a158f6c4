// `style4d study serve`: the study's web server. Participants open the page, enter their code and
// judge their pairs; each judgement is one committed row of STUDY/votes.sqlite before the page is
// told it was stored. The admin token guards the results. docs/study.md.
#pragma once
#include <atomic>
#include <filesystem>
#include <functional>
#include <string>

namespace s4d::study {

struct ServeOptions {
  std::filesystem::path study;
  std::string host = "127.0.0.1";  // localhost only unless --host says otherwise
  int port = 8080;                  // 0: any free port (printed)
  std::string admin_token;          // empty: a random one, written to STUDY/admin_token
};

// Serves until `stop` becomes true (checked every 100 ms). `on_ready(port, token)` is called once the
// socket listens. Throws std::runtime_error when the study cannot be read or the port not bound.
void serve_study(const ServeOptions& options, const std::atomic<bool>& stop,
                 const std::function<void(int port, const std::string& token)>& on_ready);

}  // namespace s4d::study
