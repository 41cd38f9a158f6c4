#include <doctest/doctest.h>

#include <chrono>
#include <sstream>
#include <string>
#include <thread>

#include "s4d/util/progress.h"

TEST_CASE("progress lines show stage, step, total, values and finish") {
  std::ostringstream out;
  s4d::util::Progress p("static", 100, out, 0.0);
  p.update(10, {{"loss", 0.125}});
  p.finish({{"psnr", 27.5}});
  const std::string text = out.str();
  CHECK(text.find("[static] 10/100 (10%)") != std::string::npos);
  CHECK(text.find("loss=0.125") != std::string::npos);
  CHECK(text.find("ETA") != std::string::npos);
  CHECK(text.find("[static] 100/100") != std::string::npos);
  CHECK(text.find("psnr=27.5") != std::string::npos);
  CHECK(text.find("done") != std::string::npos);
}

TEST_CASE("progress updates are rate-limited") {
  std::ostringstream out;
  s4d::util::Progress p("fine", 1000, out, 3600.0);
  for (int i = 1; i <= 100; ++i) p.update(static_cast<uint64_t>(i));
  CHECK(out.str().find("1/1000") != std::string::npos);
  CHECK(out.str().find("100/1000") == std::string::npos);
}

TEST_CASE("durations are formatted for people") {
  CHECK(s4d::util::format_duration(12.34) == "12.3s");
  CHECK(s4d::util::format_duration(185) == "3m05s");
  CHECK(s4d::util::format_duration(3720) == "1h02m");
}

TEST_CASE("a resumed loop's rate counts only the steps done since restart_rate") {
  std::ostringstream out;
  s4d::util::Progress p("stage 4", 100, out, 0.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  CHECK(p.format(50, {}).find("it/s") != std::string::npos);  // 50 steps in 20 ms: as if all were done now
  p.restart_rate(50);
  CHECK(p.format(50, {}).find("it/s") == std::string::npos);  // none done since: no rate, no ETA
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const std::string line = p.format(51, {});
  // One step in >= 200 ms: at most 5 it/s whatever the machine (the 50 before are not counted).
  const size_t at = line.find(" it/s");
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(line.substr(line.rfind(' ', at - 1) + 1)) <= 5.0);
}
