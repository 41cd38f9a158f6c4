// Blends of two styles of the shared 4DGS run (style_fixture.h) through `style4d render --mix --alpha`
// and `style4d view --screenshot --mix --alpha`: the ends render as each style bit for bit, the middle
// lies between the two styles' renders (and the blended MLPs' outputs between theirs), a new factor
// on an open blend (the viewer's slider) renders as a blend opened at it, the viewer's capture equals
// the offline render, the window opens on a blend, and bad blends are refused with a message and a
// non-zero exit.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "s4d/io/image_io.h"
#include "s4d/scene/trained_run.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/ref/style_mlp_ref.h"
#include "s4d/scene/style_blend.h"
#include "s4d/run/style_file.h"
#include "s4d_style_splat.h"
#include "style_fixture.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::rgb_exr;
namespace fs = std::filesystem;

const std::string kFullOptions = "--iters 60 --mlp-iters 20 --spiral-frames 4";

// The built-in style image with its channels rotated (R, G, B from B, R, G): a second style image,
// so that a style trained on it differs from "full".
std::string rotated_style_image() {
  const fs::path file = test::run4d().root / "rotated_style.png";
  if (!fs::exists(file)) {
    io::ImageF img = io::read_png(test::kBuiltinStyle);
    REQUIRE(img.channels >= 3);
    for (size_t p = 0; p < img.data.size(); p += static_cast<size_t>(img.channels))
      std::rotate(img.data.begin() + static_cast<std::ptrdiff_t>(p), img.data.begin() + static_cast<std::ptrdiff_t>(p) + 2,
                  img.data.begin() + static_cast<std::ptrdiff_t>(p) + 3);
    io::write_png(file, img);
  }
  return file.string();
}

// The two MLP styles the blends use (both with the default seed and identity initialisation).
void train_styles() {
  test::styled("full", kFullOptions);
  test::styled("full_b", kFullOptions, rotated_style_image());
}

// The exit code and the log of a `style4d` call expected to fail.
std::pair<int, std::string> refused(const std::string& command, const std::string& args, const std::string& tag) {
  const fs::path log = test::run4d().root / ("refused_" + tag + ".log");
  const int code = test::run_style4d(command, args, log);
  return {code, test::read_text(log)};
}

}  // namespace

TEST_CASE("a blend at factor 0 renders as its first style and at 1 as its second, bit for bit") {
  train_styles();
  test::styled("colors", "--method colors --iters 60 --mlp-iters 0 --spiral-frames 4");
  const std::vector<float> full = rgb_exr("--style full", "end_full"), full_b = rgb_exr("--style full_b", "end_full_b");
  REQUIRE(full != full_b);
  CHECK(rgb_exr("--style full --mix full_b --alpha 0", "end_0") == full);
  CHECK(rgb_exr("--style full --mix full_b --alpha 1", "end_1") == full_b);
  // A style without MLPs blends as zero last layers, which render like the plain rasterizer.
  CHECK(rgb_exr("--style colors --mix full --alpha 0", "end_colors") == rgb_exr("--style colors", "colors_exr"));
  // The original scene as the first style: no changes at all.
  CHECK(rgb_exr("--mix full --alpha 1", "end_original") == full);
}

TEST_CASE("a blend at factor 0.5 lies between the two styles' renders") {
  train_styles();
  const std::vector<float> a = rgb_exr("--style full", "mid_a"), b = rgb_exr("--style full_b", "mid_b");
  const std::vector<float> mid = rgb_exr("--style full --mix full_b --alpha 0.5", "mid");
  double err = 0, worst = 0, apart = 0;
  size_t outside = 0;
  for (size_t k = 0; k < mid.size(); ++k) {
    const double e = std::abs(mid[k] - 0.5 * (a[k] + b[k]));
    err += e, worst = std::max(worst, e), apart += std::abs(a[k] - b[k]);
    // Outside the two styles' values by more than float rounding.
    if (mid[k] < std::min(a[k], b[k]) - 1e-5f || mid[k] > std::max(a[k], b[k]) + 1e-5f) ++outside;
  }
  const double n = static_cast<double>(mid.size());
  MESSAGE("blend 0.5 vs the lerp of the renders: mean ", err / n, ", max ", worst, "; styles apart by mean ", apart / n,
          "; values outside the two styles' range: ", static_cast<double>(outside) / n);
  // Compositing is not linear in colour and opacity changes, so the blend is not the lerp of the
  // images. Measured on lavapipe (Mesa 22.3.6): mean error 0.0059 = 7.7% of the styles' mean
  // difference 0.076, 6.0% of the values outside the two styles' range; allowed: twice that.
  CHECK(err / n <= 0.15 * apart / n);
  CHECK(static_cast<double>(outside) / n <= 0.12);
}

TEST_CASE("the blended MLPs' outputs lie close to the lerp of the two styles' outputs") {
  train_styles();
  const run::StyleFile a = run::read_style_file(run::style_file_path(test::run4d().run, "full"));
  const run::StyleFile b = run::read_style_file(run::style_file_path(test::run4d().run, "full_b"));
  const run::StyleFile mid = scene::blend_styles(a, b, 0.5f);
  float hidden = 0;  // how far the hidden layers moved apart from the shared initialisation
  for (size_t k = 0; k < a.mlp.size(); ++k)
    if (k % S4D_STYLE_MLP_STRIDE < S4D_STYLE_MLP_W3) hidden = std::max(hidden, std::abs(a.mlp[k] - b.mlp[k]));
  // sigmoid(z) of every Gaussian's 4 outputs (dRGB = 2 s - 1, dO = s - 0.5) at the clip's start,
  // middle and end and depth features across a Gaussian's extent (relative depth, 1 / (3 x scale)).
  double err = 0, worst = 0, apart = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.count; ++i)
    for (const float t : {0.0f, 0.5f, 1.0f})
      for (const float d : {-3.0f, -1.0f, 0.0f, 1.0f, 3.0f}) {
        const size_t w = i * S4D_STYLE_MLP_STRIDE;
        const auto sa = ref::detail::style_mlp_fwd(&a.mlp[w], t, d, a.input_sigmoid).s;
        const auto sb = ref::detail::style_mlp_fwd(&b.mlp[w], t, d, a.input_sigmoid).s;
        const auto sm = ref::detail::style_mlp_fwd(&mid.mlp[w], t, d, a.input_sigmoid).s;
        for (size_t r = 0; r < 4; ++r, ++n) {
          const double e = std::abs(sm[r] - 0.5 * (sa[r] + sb[r]));
          err += e, worst = std::max(worst, e), apart += std::abs(sa[r] - sb[r]);
        }
      }
  MESSAGE("MLP outputs, weight lerp vs output lerp: mean ", err / static_cast<double>(n), ", max ", worst,
          "; styles apart by mean ", apart / static_cast<double>(n), "; hidden weights apart by at most ", hidden);
  // Measured on lavapipe's build (x86-64, float): mean 1.6e-6 = 0.05% of the styles' mean difference
  // 0.0033, max 1.4e-5, hidden weights at most 0.012 apart; allowed: about twice each.
  CHECK(err <= 1e-3 * apart);
  CHECK(worst <= 3e-5);
}

TEST_CASE("re-blending an open blend (the viewer's slider) renders as a blend opened at that factor") {
  train_styles();
  engine::Context& ctx = test::context();
  const scene::TrainedRun run = scene::read_trained_run(test::run4d().run);
  const splat::Camera cam = splat::to_splat_camera(run.dataset.views.front().camera);
  splat::Rasterizer rast(ctx);
  auto render = [&](scene::SceneSource& source) {
    rast.forward(source.at(0.5, cam), cam, run.dataset.background);
    return ctx.download<float>(rast.rgb(), size_t{cam.width} * cam.height * 3);
  };
  const std::unique_ptr<scene::BlendedScene> moved = scene::open_blend(ctx, run, "full", "full_b", 0.9f);
  const std::vector<float> before = render(*moved);
  moved->set_alpha(0.3f);
  CHECK(moved->alpha() == 0.3f);
  const std::vector<float> after = render(*moved);
  CHECK(after != before);
  CHECK(after == render(*scene::open_blend(ctx, run, "full", "full_b", 0.3f)));
}

TEST_CASE("the viewer's capture of a blend equals the offline render of that blend") {
  train_styles();
  const test::Run4d& r = test::run4d();
  const std::string blend = "--style full --mix full_b --alpha 0.3";
  const fs::path shot = r.root / "view_blend.png";
  REQUIRE_MESSAGE(test::run_style4d("view", r.run.string() + " " + blend + " --screenshot " + shot.string() +
                                                " --camera 0 --time 0.5",
                                    r.root / "view_blend.log") == 0,
                  test::read_text(r.root / "view_blend.log"));
  const io::ImageF offline = io::read_png(test::render_test_path(blend, "blend_for_view") / "0001.png");
  // Both quantise the same float image (see test_view_capture_4d.cpp): at most one level apart.
  CHECK(test::max_abs_diff(io::read_png(shot), offline) <= 1.0f / 255.0f + 1e-6f);
}

TEST_CASE("the viewer's window opens on a blend under Xvfb") {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    MESSAGE("xvfb-run is not installed (apt-get install xvfb xauth): the windowed blend test is skipped");
    return;
  }
  train_styles();
  const test::Run4d& r = test::run4d();
  const fs::path log = r.root / "view_blend_window.log";
  const std::string cmd = "xvfb-run -a -s \"-screen 0 640x480x24\" " + std::string(S4D_STYLE4D_EXE) + " view " +
                          r.run.string() + " --style full --mix full_b --alpha 0.5 --size 64x48 --exit-after 2 > " +
                          log.string() + " 2>&1";
  REQUIRE_MESSAGE(std::system(cmd.c_str()) == 0, test::read_text(log));
  CHECK(test::read_text(log).find("presented 2 frames") != std::string::npos);
  CHECK_MESSAGE(test::read_text(log).find("validation error") == std::string::npos, test::read_text(log));
}

TEST_CASE("render and view refuse a bad blend factor, half a blend, a scratch style and another Gaussian count") {
  train_styles();
  const test::Run4d& r = test::run4d();
  // A copy of the run with a scratch style's file and a style of 5 Gaussians.
  const fs::path run = test::fresh_dir("blend_refusals") / "run";
  fs::copy(r.run, run, fs::copy_options::recursive);
  run::StyleFile scratch;
  scratch.method = run::StyleMethod::scratch;
  fs::create_directories(run::style_dir(run, "retrained"));
  run::write_style_file(run::style_file_path(run, "retrained"), scratch);
  const run::StyleFile full = run::read_style_file(run::style_file_path(run, "full"));
  fs::create_directories(run::style_dir(run, "five"));
  run::write_style_file(run::style_file_path(run, "five"), scene::no_style(5, full.sh_coeffs));

  const std::string render = "--run " + run.string() + " --path test --out " + (r.root / "refused").string() + " ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {render + "--style full --mix full_b --alpha 1.5", "--alpha: expected a number in [0, 1], got '1.5'"},
      {render + "--style full --mix full_b --alpha half", "--alpha: expected a number in [0, 1], got 'half'"},
      {render + "--style full --mix full_b", "--mix full_b needs --alpha A"},
      {render + "--style full --alpha 0.5", "--alpha needs --mix NAME"},
      {render + "--style full --mix retrained --alpha 0.5", "style retrained was trained with --method scratch"},
      {render + "--style five --mix full --alpha 0.5", "trained for 5 and " + std::to_string(full.count) + " Gaussians"},
      {render + "--style full --mix nosuch --alpha 0.5", "no style nosuch"},
  };
  for (const auto& [args, message] : cases) {
    CAPTURE(args);
    const auto [code, log] = refused("render", args, "render");
    CHECK(code != 0);
    CHECK(log.find(message) != std::string::npos);
  }
  const auto [code, log] = refused("view", run.string() + " --style full --mix retrained --alpha 0.5 --screenshot " +
                                               (r.root / "refused.png").string(), "view");
  CHECK(code != 0);
  CHECK(log.find("--method scratch") != std::string::npos);
  CHECK_FALSE(fs::exists(r.root / "refused.png"));
}
