// style4d stylize on the shared 4DGS run (run4d_fixture.h): stages 3 and 4 end to end, two styles
// of one run switched at render time without retraining, the ablations, the cache of stage 3, and
// the refusals.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "s4d/io/image_io.h"
#include "s4d/metrics/flow.h"
#include "s4d/metrics/warp_loss.h"
#include "s4d/run/checkpoint.h"
#include "s4d/run/style_file.h"
#include "s4d/frame_stylizers/warp_error.h"
#include "style_fixture.h"

namespace {

using namespace s4d;
namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }

using test::render_frame;
using test::styled;
const std::string& kStyle = test::kBuiltinStyle;

// 10 log10(1 / MSE) over pixels and RGB channels (an alpha channel, if any, left out).
double psnr(const io::ImageF& a, const io::ImageF& b) {
  REQUIRE(a.width == b.width);
  REQUIRE(a.height == b.height);
  double se = 0;
  size_t n = 0;
  for (size_t p = 0; p < size_t(a.width) * size_t(a.height); ++p)
    for (int c = 0; c < 3; ++c, ++n) {
      const double d = double(a.data[p * size_t(a.channels) + size_t(c)]) - b.data[p * size_t(b.channels) + size_t(c)];
      se += d * d;
    }
  return -10.0 * std::log10(se / double(n));
}

// The .png frames of a folder in name order.
std::vector<io::ImageF> png_frames(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".png") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<io::ImageF> out;
  for (const fs::path& f : files) out.push_back(io::read_png(f));
  return out;
}

// Style4D-Bench's warp loss (L1) under the renderer's exact flow FLOW/fw_NNNN.exr, bw_NNNN.exr, mean
// over the pairs that have an unoccluded pixel.
double exact_flow_loss(const std::vector<io::ImageF>& frames, const fs::path& flow) {
  double sum = 0;
  int pairs = 0;
  for (size_t k = 0; k + 1 < frames.size(); ++k) {
    char fw[32], bw[32];
    std::snprintf(fw, sizeof fw, "fw_%04zu.exr", k);
    std::snprintf(bw, sizeof bw, "bw_%04zu.exr", k);
    const metrics::PairWarpError e =
        metrics::warp_error(frames[k], frames[k + 1], metrics::read_flow_exr(flow / fw), metrics::read_flow_exr(flow / bw));
    if (e.scored()) sum += e.error, ++pairs;
  }
  REQUIRE(pairs > 0);
  return sum / pairs;
}

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
  // Stage 4's test PSNR against the stylized frames, recomputed from the files: the saved test renders
  // (eval/cam00_000K.png) against stage 3's frames (stylized/cam00/000K.png), mean over the views. The
  // trainer scores the float render; the file rounds it to 8 bits, at most 1/510 per value, so each
  // view's RMS error moves by at most 1/510 (triangle inequality): the bound below, from the definition.
  // Measured: 14.757 dB inside [14.663, 14.850].
  const double stage4_psnr = j.at("stage4").at("test_psnr_vs_stylized").get<double>();
  double lo = 0, hi = 0;
  int views = 0;
  for (const auto& e : fs::directory_iterator(dir / "eval")) {
    std::string view = e.path().stem().string();
    view[view.find('_')] = '/';
    const double rms = std::pow(10.0, -psnr(io::read_png(e.path()), io::read_png(dir / "stylized" / (view + ".png"))) / 20.0);
    lo += -20.0 * std::log10(rms + 1.0 / 510.0);
    hi += -20.0 * std::log10(std::max(rms - 1.0 / 510.0, 1e-5));
    ++views;
  }
  REQUIRE(views == 3);  // cam00 at its 3 times
  CHECK(stage4_psnr >= lo / views);
  CHECK(stage4_psnr <= hi / views);
  // Stage 4 moved the render towards the style: the original scene's render of the same view scores
  // lower against the stylized frame than the style's render does (measured 12.66 vs 14.98 dB).
  const io::ImageF target = io::read_png(dir / "stylized" / "cam00" / "0001.png");
  CHECK(psnr(render_frame("", "original_vs_stylized"), target) < psnr(io::read_png(dir / "eval" / "cam00_0001.png"), target));

  // The warp errors, recomputed from the frames the pipeline saved. The spiral renders are read back
  // from their PNGs by the pipeline too: identical inputs, so equal up to summation (1e-9 relative).
  // The 2D stylizer's spiral frames are scored in float and saved in 8 bits: an L1 mean moves by at
  // most 2 x 1/510 (both frames of a pair rounded), never more; measured 1.4e-5 (DIS) and 5.1e-5 (exact).
  const nlohmann::json& w = j.at("warp_error");
  const nlohmann::json& exact = w.at("spiral_exact_flow");
  const std::vector<io::ImageF> original = png_frames(dir / "spiral" / "original"), styled_spiral = png_frames(dir / "spiral" / "styled"),
                                flat = png_frames(dir / "spiral" / "stylized_2d");
  REQUIRE(original.size() == 4);
  CHECK(w.at("spiral_original_render").get<double>() == doctest::Approx(frame_stylizers::warp_error(original, original)).epsilon(1e-9));
  CHECK(w.at("spiral_styled_render").get<double>() == doctest::Approx(frame_stylizers::warp_error(original, styled_spiral)).epsilon(1e-9));
  CHECK(std::abs(w.at("spiral_stylized_2d").get<double>() - frame_stylizers::warp_error(original, flat)) <= 2.0 / 510.0);
  const fs::path flow = dir / "spiral" / "original" / "flow";
  CHECK(exact.at("original_render").get<double>() == doctest::Approx(exact_flow_loss(original, flow)).epsilon(1e-9));
  CHECK(exact.at("styled_render").get<double>() == doctest::Approx(exact_flow_loss(styled_spiral, flow)).epsilon(1e-9));
  CHECK(std::abs(exact.at("stylized_2d").get<double>() - exact_flow_loss(flat, flow)) <= 2.0 / 510.0);
  // The test camera's content and 2D-stylized errors are stage 3's own for cam00 (the same frames and
  // function; stage 3 scores its float output, the test camera the saved PNGs: 2 x 1/510 again,
  // measured 4.6e-5), and
  // the run-wide values are stage 3's means over its sequences.
  const nlohmann::json& fixed = w.at("test_camera");  // cam00 over its 3 frames
  CHECK(fixed.at("frames") == 3);
  double content = 0, stylized = 0;
  const nlohmann::json* cam00 = nullptr;
  for (const nlohmann::json& seq : j.at("stage3").at("sequences")) {
    content += seq.at("content_warp_error").get<double>() / double(j.at("stage3").at("sequences").size());
    stylized += seq.at("stylized_warp_error").get<double>() / double(j.at("stage3").at("sequences").size());
    if (seq.at("name") == "cam0") cam00 = &seq;  // stage 3 names a sequence by camera index
  }
  REQUIRE(cam00 != nullptr);
  CHECK(fixed.at("content").get<double>() == doctest::Approx(cam00->at("content_warp_error").get<double>()).epsilon(1e-9));
  CHECK(std::abs(fixed.at("stylized_frames_2d").get<double>() - cam00->at("stylized_warp_error").get<double>()) <= 2.0 / 510.0);
  CHECK(w.at("content_frames").get<double>() == doctest::Approx(content).epsilon(1e-9));
  CHECK(w.at("stylized_frames_2d").get<double>() == doctest::Approx(stylized).epsilon(1e-9));
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

TEST_CASE("running the same stylize again reuses stage 3's frames and the finished stage 4, from a moved style image too") {
  const fs::path dir = styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  const test::Run4d& r = test::run4d();
  // The style keeps its own 8-bit copy of the image (the built-in style is an 8-bit PNG: equal).
  CHECK(test::max_abs_diff(io::read_png(run::style_image_path(r.run, "full")), io::read_png(kStyle)) == 0.0f);
  // The same pixels from another path are the same request.
  const fs::path moved = r.root / "moved" / "builtin.png";
  fs::create_directories(moved.parent_path());
  fs::copy_file(kStyle, moved, fs::copy_options::overwrite_existing);
  const fs::path log = r.root / "stylize_again.log";
  REQUIRE_MESSAGE(test::run_style4d("stylize", "--run " + r.run.string() + " --style " + moved.string() +
                                                   " --name full --iters 60 --mlp-iters 20 --spiral-frames 4",
                                    log) == 0,
                  test::read_text(log));
  const nlohmann::json j = read_json(dir / "stylize.json");
  CHECK(j.at("stage3").at("reused") == true);
  CHECK(j.at("stage4").at("iterations") == 60);
}

TEST_CASE("a diverging style rolls back like training does, says so, and never writes a non-finite checkpoint") {
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "stylize_diverge.log";
  // MLP weights of 1e38 overflow the hidden layers after a few steps: a NaN loss.
  const int rc = test::run_style4d("stylize", "--run " + r.run.string() + " --style " + kStyle +
                                                  " --name diverge --iters 40 --mlp-iters 30 --mlp-lr 1e38 --spiral-frames 2",
                                   log);
  const std::string text = test::read_text(log);
  INFO(text);
  CHECK(text.find("stage 4: the loss became non-finite") != std::string::npos);
  CHECK(text.find("rolled back") != std::string::npos);
  if (rc != 0) CHECK((text.find("diverged") != std::string::npos || text.find("not finite") != std::string::npos));
  const fs::path checkpoint = r.run / "style" / "diverge" / "checkpoint.s4dckpt";
  if (fs::exists(checkpoint)) CHECK_NOTHROW(run::read_checkpoint(checkpoint));
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

TEST_CASE("--style-setting paper trains the MLPs from the first step, two views a step, and is recorded for resume checks") {
  const fs::path dir = styled("paper", "--style-setting paper --iters 20 --spiral-frames 2");
  const nlohmann::json settings = read_json(dir / "stylize.json").at("settings");
  CHECK(settings.at("setting") == "paper");
  CHECK(settings.at("mlp_iterations") == 20);
  CHECK(settings.at("batch") == 2);
  CHECK(settings.at("mlp_lr") == 1e-4);
  CHECK(settings.at("mlp_lr_final") == 1e-5);
  CHECK(settings.at("mlp_init") == "uniform");
  CHECK(read_json(dir / "request.json").at("settings") == settings);
  // The style file holds the MLPs and the same settings.
  const run::StyleFile file = run::read_style_file(run::style_file_path(test::run4d().run, "paper"));
  REQUIRE(file.method == run::StyleMethod::full);
  CHECK(file.settings == settings);
  CHECK(std::any_of(file.mlp.begin(), file.mlp.end(), [](float w) { return w != 0; }));
  // The same name with the tuned setting is other settings.
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "stylize_paper_refused.log";
  CHECK(test::run_style4d("stylize", "--run " + r.run.string() + " --style " + kStyle + " --name paper --iters 20 --mlp-iters 20 --spiral-frames 2",
                          log) != 0);
  CHECK(test::read_text(log).find("--restart") != std::string::npos);
  CHECK(test::run_style4d("stylize", "--run " + r.run.string() + " --style " + kStyle + " --style-setting fast", log) != 0);
  CHECK(test::read_text(log).find("setting 'fast' is not tuned or paper") != std::string::npos);
}

TEST_CASE("stylize --time-budget plans stage 4 from its measured steps, records how the time went, and continues with its plan") {
  const fs::path dir = styled("budget", "--time-budget 20s --spiral-frames 4");
  const nlohmann::json j = read_json(dir / "stylize.json");
  const nlohmann::json& b = j.at("time_budget");
  CHECK(b.at("given_seconds") == 20.0);
  CHECK(b.at("took_seconds") == j.at("seconds"));
  CHECK(read_json(dir / "request.json").at("time_budget") == 20.0);
  // Stage 4 was given what stage 3 and the spiral's original render left, less the reserve after it
  // (a thousandth of a second when nothing was left).
  const double deadline = b.at("stage4_deadline_seconds").get<double>();
  CHECK((b.at("stage3_seconds").get<double>() + b.at("spiral_original_seconds").get<double>() + deadline +
             b.at("reserve_seconds").get<double>() <= 20.0 + 1e-6 ||
         deadline == 1e-3));
  // The reserve: three quarters of the spiral's original part again, and 3 % for the closing test.
  CHECK(b.at("reserve_seconds").get<double>() ==
        doctest::Approx(0.75 * b.at("spiral_original_seconds").get<double>() + 0.03 * 20.0));
  // The first plan 30 steps after the 20 untimed ones, before the MLPs join; the style ran the
  // last plan's lengths, and its file records them.
  const nlohmann::json& s4 = j.at("stage4");
  const nlohmann::json& plans = s4.at("time_budget").at("plans");
  REQUIRE(plans.size() >= 1);
  CHECK(plans[0].at("iteration") == 50);
  CHECK(plans[0].at("phase") == "colors");
  CHECK(s4.at("time_budget").at("start_iterations") == 1500);
  const nlohmann::json& last = plans.back();
  CHECK(s4.at("iterations") == last.at("iterations"));
  const run::StyleFile file = run::read_style_file(run::style_file_path(test::run4d().run, "budget"));
  CHECK(file.settings.at("iterations") == last.at("iterations"));
  CHECK(file.settings.at("mlp_iterations") == last.at("mlp_iterations"));
  // The same command again continues the planned style (it is finished) instead of refusing it.
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "stylize_budget_again.log";
  REQUIRE_MESSAGE(test::run_style4d("stylize", "--run " + r.run.string() + " --style-image " + kStyle +
                                                   " --style budget --time-budget 20s --spiral-frames 4",
                                    log) == 0,
                  test::read_text(log));
  CHECK(read_json(dir / "stylize.json").at("stage4").at("iterations") == last.at("iterations"));
  // Another budget is another request.
  CHECK(test::run_style4d("stylize", "--run " + r.run.string() + " --style-image " + kStyle +
                                         " --style budget --time-budget 30s --spiral-frames 4",
                          log) != 0);
  CHECK(test::read_text(log).find("--restart") != std::string::npos);
}
