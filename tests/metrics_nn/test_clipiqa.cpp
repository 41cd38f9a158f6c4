// CLIP-IQA+'s host parts (bench/metrics/clipiqa.cpp) without torch: the score's softmax over the
// prompt pair and the errors for weight files that are not a CLIP ResNet. The network and the whole
// metric against PyTorch: torch_reference_clipiqa.py.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/io/safetensors.h"
#include "s4d/metrics/clipiqa.h"
#include "nn_fixture.h"
#include "test_context.h"

using namespace s4d;

TEST_CASE("clipiqa_score is the good prompt's softmax probability over the scaled cosines") {
  // cos(f, good) = 1, cos(f, bad) = 0: 1 / (1 + exp(-scale)); features need not be unit vectors.
  CHECK(metrics::clipiqa_score({3.0, 0.0}, {2.0, 0.0}, {0.0, 5.0}, 2.0) == doctest::Approx(1.0 / (1.0 + std::exp(-2.0))));
  // cos 0.6 and -0.8: the logit is scale (0.6 + 0.8), 1 at scale 1 / 1.4.
  const double p = metrics::clipiqa_score({0.6, 0.8}, {1.0, 0.0}, {0.0, -1.0}, 1.0 / 1.4);
  CHECK(p == doctest::Approx(1.0 / (1.0 + std::exp(-1.0))));
  CHECK(metrics::clipiqa_score({1.0, 2.0, 3.0}, {1.0, 1.0, 0.0}, {1.0, 1.0, 0.0}, 100.0) == 0.5);
  // Swapping the prompts gives the complement.
  const double a = metrics::clipiqa_score({0.3, -0.2, 0.9}, {0.1, 0.4, 0.2}, {0.5, -0.1, 0.3}, 100.0);
  const double b = metrics::clipiqa_score({0.3, -0.2, 0.9}, {0.5, -0.1, 0.3}, {0.1, 0.4, 0.2}, 100.0);
  CHECK(a + b == doctest::Approx(1.0).epsilon(1e-12));
  CHECK_THROWS_AS(metrics::clipiqa_score({0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, 100.0), std::invalid_argument);
  CHECK_THROWS_AS(metrics::clipiqa_score({1.0, 0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, 100.0), std::invalid_argument);
}

TEST_CASE("a weight file that is not a CLIP ResNet is refused naming the file and the tensor") {
  test::ScratchDir dir("clipiqa");
  const auto expect_refused = [&](const std::vector<io::NamedTensor>& tensors, const std::string& tensor) {
    const auto path = dir / "clipiqa_plus.safetensors";
    io::write_safetensors(path, tensors);
    try {
      metrics::ClipIqaPlus clip(test::context(), io::SafetensorsFile(path));
      FAIL("an incomplete file loaded");
    } catch (const std::exception& e) {
      CHECK(std::string(e.what()).find("clipiqa_plus.safetensors") != std::string::npos);
      CHECK_MESSAGE(std::string(e.what()).find(tensor) != std::string::npos, e.what());
    }
  };
  // A ViT's conv1 where the ResNet's stem should be: conv3 missing.
  expect_refused({{"visual.conv1.weight", {768, 3, 16, 16}, std::vector<float>(768 * 3 * 256, 0.1f)}}, "visual.conv3.weight");
  expect_refused({{"visual.conv3.weight", {3, 1, 3, 3}, std::vector<float>(9 * 3, 0.1f)}},
                 "visual.conv3.weight has shape [3, 1, 3, 3]");
  // A width-2 stem: conv1 is the next tensor read.
  expect_refused({{"visual.conv3.weight", {2, 1, 3, 3}, std::vector<float>(18, 0.1f)}}, "visual.conv1.weight");
}
