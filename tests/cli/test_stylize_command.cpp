// style4d stylize on the shared 4DGS run (run4d_fixture.h): stages 3 and 4 end to end, two styles
// of one run switched at render time without retraining, the ablations, the cache of stage 3, and
// the refusals.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "s4d/io/image_io.h"
#include "style_fixture.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }

using test::render_frame;
using test::styled;
const std::string& kStyle = test::kBuiltinStyle;

double mean_abs_diff(const io::ImageF& a, const io::ImageF& b) {
  double sum = 0;
  for (size_t i = 0; i < a.data.size(); ++i) sum += std::abs(a.data[i] - b.data[i]);
  return sum / static_cast<double>(a.data.size());
}

}  // namespace

TEST_CASE("stylize trains a style: stylize.json, the style file, the stylized frames, spiral renders and a contact sheet") {
  const fs::path dir = styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  const nlohmann::json j = read_json(dir / "stylize.json");
  CHECK(j.at("method") == "full");
  CHECK(j.at("stylizer") == "patch");
  CHECK(j.at("stage3").at("frames") == 12);  // 4 cameras x 3 frames
  CHECK(j.at("stage4").at("iterations") == 60);
  CHECK(std::isfinite(j.at("stage4").at("test_psnr_vs_stylized").get<double>()));
  for (const char* k : {"spiral_styled_render", "spiral_original_render", "spiral_stylized_2d", "stylized_frames_2d", "content_frames"})
    CHECK(j.at("warp_error").at(k).get<double>() >= 0);
  for (const char* k : {"original_render", "styled_render", "stylized_2d"})
    CHECK(j.at("warp_error").at("spiral_exact_flow").at(k).get<double>() >= 0);
  const nlohmann::json& fixed = j.at("warp_error").at("test_camera");  // cam00 over its 3 frames
  CHECK(fixed.at("frames") == 3);
  for (const char* k : {"content", "stylized_frames_2d", "styled_render"}) CHECK(fixed.at(k).get<double>() >= 0);
  CHECK(fs::exists(dir / "style.s4dstyle"));
  CHECK(fs::exists(dir / "contact_sheet.png"));
  CHECK(fs::exists(dir / "spiral" / "stylized_2d" / "0003.png"));  // the 2D baseline on the spiral's 4 frames
  CHECK(fs::exists(dir / "stylized" / "cam01" / "0002.png"));
  CHECK(fs::exists(dir / "spiral" / "styled" / "frames.json"));
  CHECK(fs::exists(dir / "eval"));
}

TEST_CASE("two styles of one run switch at render time without retraining, and differ from the original") {
  styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  styled("colors", "--method colors --iters 60 --mlp-iters 0 --spiral-frames 4");
  const io::ImageF original = render_frame("", "original"), a = render_frame("full", "full"), b = render_frame("colors", "colors");
  // Measured mean differences on this fixture: 0.074 (full) and 0.070 (colors) from the original,
  // 0.0049 between the two styles.
  CHECK(mean_abs_diff(original, a) > 0.02);
  CHECK(mean_abs_diff(original, b) > 0.02);
  CHECK(mean_abs_diff(a, b) > 0.002);
  CHECK(test::max_abs_diff(render_frame("full", "full_again"), a) == 0.0f);  // the same style renders the same
}

TEST_CASE("the viewer's capture of a style matches the offline render of that style") {
  styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  const test::Run4d& r = test::run4d();
  const fs::path shot = r.root / "view_full.png";
  REQUIRE_MESSAGE(test::run_style4d("view", r.run.string() + " --style full --screenshot " + shot.string() + " --camera 0 --time 0.5",
                                    r.root / "view_full.log") == 0,
                  test::read_text(r.root / "view_full.log"));
  // Both quantise the same float image (see test_view_capture_4d.cpp): at most one level apart.
  CHECK(test::max_abs_diff(io::read_png(shot), render_frame("full", "full_for_view")) <= 1.0f / 255.0f + 1e-6f);
}

TEST_CASE("running the same stylize again reuses stage 3's frames and the finished stage 4") {
  const fs::path dir = styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "stylize_again.log";
  REQUIRE(test::run_style4d("stylize", "--run " + r.run.string() + " --style " + kStyle + " --name full --iters 60 --mlp-iters 20 --spiral-frames 4",
                            log) == 0);
  const nlohmann::json j = read_json(dir / "stylize.json");
  CHECK(j.at("stage3").at("reused") == true);
  CHECK(j.at("stage4").at("iterations") == 60);
}

TEST_CASE("stylize refuses other settings under an existing name, an unknown method and a missing style image") {
  styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "stylize_refused.log";
  CHECK(test::run_style4d("stylize", "--run " + r.run.string() + " --style " + kStyle + " --name full --iters 61 --mlp-iters 20", log) != 0);
  CHECK(test::read_text(log).find("--restart") != std::string::npos);
  CHECK(test::run_style4d("stylize", "--run " + r.run.string() + " --style " + kStyle + " --method paint", log) != 0);
  CHECK(test::read_text(log).find("method 'paint'") != std::string::npos);
  CHECK(test::run_style4d("stylize", "--run " + r.run.string() + " --style /no/such.png", log) != 0);
  CHECK(test::read_text(log).find("/no/such.png") != std::string::npos);
  CHECK(test::run_style4d("render", "--run " + r.run.string() + " --style nosuch --path test --out " + (r.root / "x").string(), log) != 0);
  CHECK(test::read_text(log).find("no style nosuch") != std::string::npos);
}
