// Styles of the shared 4DGS run (run4d_fixture.h), each trained once per test process, and renders
// of the run's test camera in a style or a blend of two, for the tests of stylize and of blending.
#pragma once
#include <doctest/doctest.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "run4d_fixture.h"
#include "s4d/io/image_io.h"

namespace s4d::test {

inline const std::string kBuiltinStyle = std::string(S4D_SOURCE_DIR) + "/assets/styles/builtin.png";

// Trains style `name` of the fixture run once per process from `image` with `options`.
inline const std::filesystem::path& styled(const std::string& name, const std::string& options,
                                           const std::string& image = kBuiltinStyle) {
  static std::map<std::string, std::filesystem::path> done;
  if (!done.count(name)) {
    const Run4d& r = run4d();
    const std::filesystem::path log = r.root / ("stylize_" + name + ".log");
    REQUIRE_MESSAGE(run_style4d("stylize", "--run " + r.run.string() + " --style-image " + image + " --style " + name + " " + options,
                                log) == 0,
                    read_text(log));
    done[name] = r.run / "style" / name;
  }
  return done.at(name);
}

// `style4d render --run RUN --path test <style_args> --format FORMAT` into a fresh folder named by
// `tag`; returns the folder of the test camera's frames (cam00/0000..0002).
inline std::filesystem::path render_test_path(const std::string& style_args, const std::string& tag,
                                              const std::string& format = "png") {
  const Run4d& r = run4d();
  const std::filesystem::path out = r.root / ("render_" + tag), log = r.root / ("render_" + tag + ".log");
  std::filesystem::remove_all(out);
  REQUIRE_MESSAGE(run_style4d("render", "--run " + r.run.string() + " " + style_args + " --path test --format " + format +
                                            " --out " + out.string(),
                              log) == 0,
                  read_text(log));
  return out / "cam00";
}

// R, G, B of the test camera's three EXR frames, rendered with `style_args`.
inline std::vector<float> rgb_exr(const std::string& style_args, const std::string& tag) {
  const std::filesystem::path dir = render_test_path(style_args, tag, "exr");
  std::vector<float> out;
  for (int k = 0; k < 3; ++k) {
    const io::ExrImage img = io::read_exr(dir / ("000" + std::to_string(k) + ".exr"));
    for (const char* c : {"R", "G", "B"}) out.insert(out.end(), img.channels.at(c).begin(), img.channels.at(c).end());
  }
  return out;
}

// The test camera's middle frame (t = 0.5) in `style` ("" for the original scene).
inline io::ImageF render_frame(const std::string& style, const std::string& tag) {
  return io::read_png(render_test_path(style.empty() ? "" : "--style " + style, tag) / "0001.png");
}

}  // namespace s4d::test
