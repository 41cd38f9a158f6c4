// study plan on bench reports written here (a frames-mode report and a run-mode one with its
// renders' folder layout, over PNG frames): the pairs, the single frames and where they are
// picked, the attention checks, each participant's order, seeded repeatability, the WebM videos
// (decoded back), and the refusals.
#include <doctest/doctest.h>

#include <fstream>
#include <opencv2/videoio.hpp>
#include <set>
#include <unistd.h>

#include "s4d/io/image_io.h"
#include "study_dirs.h"
#include "s4d/study/study_plan.h"

using namespace s4d;
using namespace s4d::study;
namespace fs = std::filesystem;

namespace {

using s4d::study::test::fresh;

// n frames of w x h whose colour encodes the method and the frame index.
void frames(const fs::path& dir, int n, int w, int h, float method) {
  fs::create_directories(dir);
  for (int k = 0; k < n; ++k) {
    io::ImageF im{w, h, 3, std::vector<float>(static_cast<size_t>(w) * h * 3)};
    for (size_t i = 0; i < im.data.size(); i += 3) {
      im.data[i] = method;
      im.data[i + 1] = static_cast<float>(k) / static_cast<float>(n);
      im.data[i + 2] = static_cast<float>(i % 97) / 97.0f;
    }
    char name[16];
    std::snprintf(name, sizeof name, "%04d.png", k);
    io::write_png(dir / name, im);
  }
}

void write(const fs::path& file, const nlohmann::json& j) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << j.dump(1);
}

// Bench outputs: a frames-mode report of methods m1, m2 (and the original, left out) and a run-mode
// report of styles full and colors with one test camera and the spiral.
std::vector<fs::path> bench_outputs(const fs::path& root) {
  frames(root / "v/m1", 10, 16, 12, 0.2f);
  frames(root / "v/m2", 10, 16, 12, 0.8f);
  write(root / "v/report.json",
        {{"mode", "frames"},
         {"results", {{{"method", "m1"}, {"scene", "s"}, {"style", "st"}, {"inputs", {{"frames", (root / "v/m1").string()}}}},
                      {{"method", "m2"}, {"scene", "s"}, {"style", "st"}, {"inputs", {{"frames", (root / "v/m2").string()}}}},
                      {{"method", "original"}, {"scene", "s"}, {"style", "st"}, {"inputs", {{"frames", (root / "v/m1").string()}}}}}}});
  for (const char* m : {"full", "colors"}) {
    const float c = std::string(m) == "full" ? 0.4f : 0.6f;
    frames(root / "r/renders" / m / "test/cam00", 6, 15, 11, c);  // odd sides: padded for the video
    frames(root / "r/renders" / m / "spiral", 8, 15, 11, c);
  }
  // Inputs recorded relative to another working directory: found under the report's renders/.
  auto result = [](const char* m) {
    return nlohmann::json{{"method", m}, {"scene", "synth"}, {"style", "builtin"},
                          {"inputs", {{"test", std::string("elsewhere/renders/") + m + "/test"}, {"spiral", "elsewhere/x"}}}};
  };
  write(root / "r/report.json", {{"mode", "run"}, {"results", {result("full"), result("colors")}}});
  return {root / "v", root / "r/report.json"};
}

int decoded_frames(const fs::path& webm, cv::Mat* first = nullptr) {
  cv::VideoCapture cap(webm.string(), cv::CAP_FFMPEG);
  REQUIRE_MESSAGE(cap.isOpened(), webm.string());
  int n = 0;
  for (cv::Mat m; cap.read(m); ++n)
    if (n == 0 && first) *first = m.clone();
  return n;
}

}  // namespace

TEST_CASE("study plan: pairs, frames, checks, participants, media") {
  const fs::path root = fresh("plan");
  PlanOptions o;
  o.reports = bench_outputs(root);
  o.out = root / "study";
  o.participants = 5;
  o.seed = 7;
  o.frame_pairs_4d = 3;
  o.frame_pairs_video = 2;
  const Study s = plan_study(o);

  std::map<std::string, int> count;
  for (const Item& it : s.items) ++count[it.part + "/" + it.kind + "/" + it.check];
  CHECK(count["4d/video/"] == 2);  // full vs colors on test/cam00 and on the spiral
  CHECK(count["video/video/"] == 1);  // m1 vs m2 (the original is not a method)
  CHECK(count["4d/frame/"] == 3);
  CHECK(count["video/frame/"] == 2);
  CHECK(count["4d/video/identical"] == 1);
  CHECK(count["4d/video/broken"] == 1);
  REQUIRE(s.parts.size() == 2);
  CHECK(s.parts[0].id == "4d");

  // Part 2's two frames come from its one 10-frame pair at the middles of two halves: 2 and 7.
  std::vector<std::string> picked;
  for (const Item& it : s.items)
    if (it.part == "video" && it.kind == "frame") picked.push_back(it.media[0]);
  REQUIRE(picked.size() == 2);
  CHECK(picked[0] == "media/video/s/st/frames/m1_f0002.png");
  CHECK(picked[1] == "media/video/s/st/frames/m1_f0007.png");
  // The frame is the bench's own, unchanged.
  const io::ImageF still = io::read_png(o.out / picked[1]), source = io::read_png(root / "v/m1/0007.png");
  CHECK(still.data == source.data);

  // Every participant sees every item once, Part 1 before Part 2, videos before frames; sides vary.
  std::set<std::string> codes;
  int swaps = 0, placements = 0;
  for (const Participant& p : s.participants) {
    codes.insert(p.code);
    CHECK(p.code.size() == 8);
    std::multiset<std::string> seen;
    std::string last_block;
    std::vector<std::string> blocks;
    for (const Placement& pl : p.order) {
      seen.insert(pl.item);
      const Item& it = s.item(pl.item);
      if (it.part + it.kind != last_block) blocks.push_back(last_block = it.part + it.kind);
      swaps += pl.swap ? 1 : 0;
      ++placements;
    }
    CHECK(seen.size() == s.items.size());
    CHECK(std::set<std::string>(seen.begin(), seen.end()).size() == s.items.size());
    CHECK(blocks == std::vector<std::string>{"4dvideo", "4dframe", "videovideo", "videoframe"});
  }
  CHECK(codes.size() == 5);
  CHECK(swaps > 0);
  CHECK(swaps < placements);

  // The videos decode to their frame counts; the odd 15x11 renders became 16x12; the broken copy is far
  // from the intact one.
  const Item& broken = *std::find_if(s.items.begin(), s.items.end(), [](const Item& it) { return it.check == "broken"; });
  cv::Mat intact_first, broken_first;
  CHECK(broken.view == "spiral");  // the first pair in view order
  CHECK(decoded_frames(o.out / broken.media[0], &intact_first) == 8);
  CHECK(decoded_frames(o.out / broken.media[1], &broken_first) == 8);
  CHECK(intact_first.cols == 16);
  CHECK(intact_first.rows == 12);
  CHECK(cv::norm(intact_first, broken_first, cv::NORM_L1) / static_cast<double>(intact_first.total() * 3) > 30.0);
  CHECK(decoded_frames(o.out / "media/video/s/st/frames/m2.webm") == 10);

  // The same seed plans the same study; a second plan into the folder is refused.
  PlanOptions again = o;
  again.out = root / "study2";
  plan_study(again);
  std::ifstream a(o.out / "study.json"), b(again.out / "study.json");
  CHECK(std::string(std::istreambuf_iterator<char>(a), {}) == std::string(std::istreambuf_iterator<char>(b), {}));
  CHECK_THROWS_WITH_AS(plan_study(o), doctest::Contains("already holds a study"), std::invalid_argument);
  // The study file reads back as written.
  const Study read = read_study(o.out);
  CHECK(to_json(read) == to_json(s));
  fs::remove_all(root);
}

TEST_CASE("study plan: refusals name the file and the field") {
  const fs::path root = fresh("plan_bad");
  PlanOptions o;
  o.out = root / "study";
  o.reports = {root / "missing"};
  CHECK_THROWS_WITH_AS(plan_study(o), doctest::Contains("missing: does not exist"), std::runtime_error);
  write(root / "one/report.json", {{"results", {{{"method", "m1"}, {"scene", "s"}, {"style", "st"}}}}});
  o.reports = {root / "one"};
  CHECK_THROWS_WITH_AS(plan_study(o), doctest::Contains("report.json: results[0].inputs: missing"), std::runtime_error);
  frames(root / "f", 3, 8, 8, 0.5f);
  write(root / "two/report.json",
        {{"results", {{{"method", "m1"}, {"scene", "s"}, {"style", "st"}, {"inputs", {{"frames", (root / "f").string()}}}}}}});
  o.reports = {root / "two"};
  CHECK_THROWS_WITH_AS(plan_study(o), doctest::Contains("no scene, style and view has two methods"), std::invalid_argument);
  o.participants = 0;
  CHECK_THROWS_WITH_AS(plan_study(o), doctest::Contains("--participants"), std::invalid_argument);
  CHECK_FALSE(fs::exists(o.out / "study.json"));
  fs::remove_all(root);
}
