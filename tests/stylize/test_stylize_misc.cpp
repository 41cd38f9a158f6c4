// The registry's names and errors and the built-in style generator.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "s4d/frame_stylizers/builtin_style.h"
#include "s4d/frame_stylizers/registry.h"

using namespace s4d;

TEST_CASE("registry makes the patch stylizer and explains the others") {
  CHECK(frame_stylizers::stylizer_names() == std::vector<std::string>{"patch", "adain", "adaattn", "mccnet", "hgst"});
  CHECK(frame_stylizers::make_stylizer("patch")->name() == "patch");
  CHECK_THROWS_WITH_AS(frame_stylizers::make_stylizer("patch", {.weights = "w"}),
                       "patch needs no weights; --weights is for adain, adaattn, mccnet, hgst", std::invalid_argument);
  // Network stylizers never run without weights; the message says which files they need.
  CHECK_THROWS_WITH_AS(frame_stylizers::make_stylizer("adain"),
                       doctest::Contains("adain needs weights: --weights DIR holding vgg_normalised.safetensors and "
                                         "decoder.safetensors"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(frame_stylizers::make_stylizer("hgst"),
                       doctest::Contains("hgst needs weights: --weights DIR holding vgg_normalised.safetensors, "
                                         "decoder.safetensors and mcc_module.safetensors"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(frame_stylizers::make_stylizer("mccnet", {.weights = "/nonexistent/weights"}),
                       doctest::Contains("--weights /nonexistent/weights is not a folder"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(frame_stylizers::make_stylizer("adaattn"),
                       doctest::Contains("adaattn needs weights: --weights DIR holding vgg_normalised.safetensors, "
                                         "net_adaattn_3.safetensors, net_transformer.safetensors and "
                                         "net_decoder.safetensors"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(frame_stylizers::make_stylizer("nope"), doctest::Contains("available: patch, adain, adaattn, mccnet, hgst"),
                       std::invalid_argument);
}

TEST_CASE("built-in style is deterministic, painted and seed-dependent") {
  const io::ImageF a = frame_stylizers::builtin_style(64, 3), b = frame_stylizers::builtin_style(64, 3), c = frame_stylizers::builtin_style(64, 4);
  CHECK(a.width == 64);
  CHECK(a.height == 64);
  CHECK(a.data == b.data);
  CHECK(a.data != c.data);
  CHECK_THROWS_AS(frame_stylizers::builtin_style(16), std::invalid_argument);
}

TEST_CASE("the committed built-in style is the generator's output") {
  const io::ImageF committed = io::read_png(S4D_BUILTIN_STYLE_PNG);
  const io::ImageF generated = frame_stylizers::builtin_style();
  REQUIRE(committed.width == generated.width);
  REQUIRE(committed.height == generated.height);
  double worst = 0;
  for (size_t i = 0; i < generated.data.size(); ++i)
    worst = std::max(worst, static_cast<double>(std::abs(committed.data[i] - generated.data[i])));
  CHECK(worst <= 0.5 / 255 + 1e-6);  // 8-bit rounding only
}
