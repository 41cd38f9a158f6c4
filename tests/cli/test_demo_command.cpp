// style4d demo end to end with every stage shortened: each stage recorded with its time and device
// memory, the bench table in the report with both methods, the videos decodable with the protocol's
// frame count, and the report's sections present.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "s4d/data/video_reader.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

int decoded_frames(const fs::path& video) {
  data::VideoReader reader(video);
  int n = 0;
  while (reader.next()) ++n;
  return n;
}

}  // namespace

TEST_CASE("demo runs every stage of the pipeline and reports each stage's time and memory") {
  const fs::path dir = test::fresh_dir("demo");
  const fs::path out = dir / "demo", log = dir / "demo.log";
  REQUIRE_MESSAGE(test::run_style4d("demo", "--out " + out.string() + " --keys 4096 --iters 30 --fine-iters 10 --style-iters 10 "
                                                                      "--mlp-iters 5 --spiral-frames 4", log) == 0,
                  test::read_text(log));
  const nlohmann::json j = nlohmann::json::parse(test::read_text(out / "demo.json"));
  CHECK(j.at("engine_ok") == true);
  CHECK(j.at("complete") == true);
  std::vector<std::string> names;
  for (const auto& s : j.at("stages")) {
    names.push_back(s.at("stage"));
    CHECK(s.at("seconds").get<double>() >= 0);
  }
  CHECK(names == std::vector<std::string>{"synth", "engine", "train", "stylize", "bench", "videos"});
  for (const auto& s : j.at("stages"))
    if (s.at("stage") == "train" || s.at("stage") == "stylize") CHECK(s.at("device_peak_mib").get<double>() > 0.1);
  CHECK(j.at("host_peak_mib").get<double>() > 1);
  CHECK(j.at("train").at("fine_iterations") == 10);
  CHECK(j.at("train").at("test_psnr").get<double>() > 10);  // a 40-iteration fit still beats noise; measured 18.7 at 90
  const auto& results = j.at("bench").at("results");
  REQUIRE(results.size() == 2);
  CHECK(results[0].at("method") == "original");
  CHECK(results[1].at("method") == "builtin");
  for (const auto& r : results)
    for (const char* k : {"uiqm", "warp_loss", "content_ssim"}) CHECK_MESSAGE(r.at(k).is_number(), k);
  for (const auto& v : j.at("videos")) {
    const std::string name = v.get<std::string>();
    CHECK_MESSAGE(decoded_frames(out / name) == (name.find("spiral") != std::string::npos ? 4 : 30), name);
  }
  CHECK(j.at("videos").size() == 4);
  const std::string md = test::read_text(out / "report.md");
  for (const char* section : {"## Stages", "## Stages 1-2", "## Stages 3-4", "## Style4D-Bench", "## Videos", "| builtin |"})
    CHECK_MESSAGE(md.find(section) != std::string::npos, section);
  CHECK(fs::file_size(out / "bench" / "report.html") > 1000);  // the bench's page, linked from report.md
  fs::remove_all(dir);
}
