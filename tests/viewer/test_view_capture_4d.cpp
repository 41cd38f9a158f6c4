// `style4d view RUN --screenshot` of a 4DGS run: captures follow the scene's motion, each equal to the
// offline protocol render of the same camera at the same time.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "run4d_fixture.h"
#include "s4d/io/image_io.h"

namespace fs = std::filesystem;
using s4d::test::max_abs_diff;
using s4d::test::read_text;
using s4d::test::run_style4d;

TEST_CASE("captures of a 4DGS run match the offline render at each time and differ between times") {
  const s4d::test::Run4d& r = s4d::test::run4d();
  const fs::path dir = s4d::test::fresh_dir("view_capture_4d");
  const fs::path protocol = dir / "protocol";
  REQUIRE(run_style4d("render", "--run " + r.run.string() + " --path test --out " + protocol.string(), dir / "run.log") == 0);
  for (const auto& [time, k] : {std::pair{"0", 0}, {"0.5", 1}, {"1", 2}}) {
    const fs::path shot = dir / s4d::test::png_name("t", k);
    REQUIRE_MESSAGE(run_style4d("view", r.run.string() + " --screenshot " + shot.string() + " --camera 0 --time " + time,
                                dir / "view.log") == 0,
                    read_text(dir / "view.log"));
    const s4d::io::ImageF offline = s4d::io::read_png(protocol / "cam00" / s4d::test::png_name("000", k));
    // Both quantise the same float image: present_pack in float, write_png in double, so a value
    // within float rounding of a level boundary may land one level apart. Measured worst case on
    // lavapipe (Mesa 22.3.6, LLVM 15): 0 levels; allowed: 1 level.
    CHECK_MESSAGE(max_abs_diff(s4d::io::read_png(shot), offline) <= 1.0f / 255.0f + 1e-6f, "t = " << time);
  }
  // The scene moves between t = 0 and t = 1 (where, test_render_4d.cpp checks against the ground
  // truth). Measured largest change on lavapipe: 0.059 (15 levels); required: half of it.
  CHECK(max_abs_diff(s4d::io::read_png(dir / "t0.png"), s4d::io::read_png(dir / "t2.png")) > 0.03f);
}
