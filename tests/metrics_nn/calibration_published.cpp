// The native learned metrics against their published calibration values (METRICS.md 5 and 9):
// pyiqa's ResultsCalibra pairs (TID2013 crops, dist_dir/I03..I19 against ref_dir/I03..I19, no
// resize) scored by the authors' own code: DISTS 0.4742, 0.1424, 0.0682, 0.0287, 0.3123, LPIPS
// v0.1 AlexNet ([0, 1] inputs, 2x - 1) 0.7237, 0.2572, 0.0508, 0.0521, 0.4253 and CKDN (ckdn(dist,
// ref), the authors' PIL preprocessing) 0.2833, 0.5766, 0.6367, 0.6579, 0.5999; MUSIQ (no reference,
// the dist_dir images) as pyiqa's port scores them, KonIQ 12.4785, 75.7772, 73.7454, 75.4609, 38.0257
// and PaQ-2-PiQ 46.0196, 72.6655, 73.7657, 74.3880, 69.7233 (METRICS.md 3).
//
// Needs what cannot ship with the project: the published weights converted by
// tools/convert_weights.py (S4D_METRIC_WEIGHTS: vgg16, dists, alexnet, lpips_alex, ckdn, musiq,
// musiq_paq2piq .safetensors)
// and the calibration images (S4D_CALIBRATION_DIR: a copy of pyiqa's ResultsCalibra with ref_dir/
// and dist_dir/). Each metric runs when its files are there; otherwise it is reported as skipped
// with what is missing, and when nothing could run the program exits 77 (ctest: skipped).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/metrics/ckdn.h"
#include "s4d/metrics/dists.h"
#include "s4d/metrics/lpips.h"
#include "s4d/metrics/musiq.h"
#include "s4d/io/image_file.h"

namespace {

namespace fs = std::filesystem;
using namespace s4d;

const std::vector<std::string> kImages = {"I03", "I04", "I06", "I08", "I19"};
// The authors' values, printed to 4 decimals; pyiqa's own port differs from them by up to 1e-4
// (DISTS I06, LPIPS I03). 1e-3 allows both roundings plus float32 accumulation on another device.
// No measured worst case: neither the weights nor the images are on the machines this was written on.
constexpr double kTolerance = 1e-3;
// CKDN: pyiqa resizes tensors with torchvision where the authors used PIL, and its own port scores
// 0.2840, 0.5650, 0.6263, 0.6414, 0.5935 (2.5 % from the authors' at I08); pyiqa's test allows a
// relative 3 %, and so does this one.
constexpr double kCkdnRelativeTolerance = 0.03;
// MUSIQ: the values of pyiqa's port, which the native one follows (bicubic scales where the authors'
// TensorFlow code resized with a Gaussian kernel: their values differ from pyiqa's by up to 2.9 %, at
// I19), printed to 4 decimals; 1e-3 relative allows float32 accumulation on another device. No
// measured worst case: neither the weights nor the images are on the machines this was written on.
constexpr double kMusiqRelativeTolerance = 1e-3;

struct Calibration {
  std::string metric;
  std::vector<std::string> weights;  // files under S4D_METRIC_WEIGHTS
  std::vector<double> published;     // per kImages
  double relative_tolerance = 0;     // 0: kTolerance absolute
};

fs::path env_path(const char* name) {
  const char* v = std::getenv(name);
  return v ? fs::path(v) : fs::path();
}

// What keeps a metric from running, or empty.
std::string missing(const Calibration& c, const fs::path& weights, const fs::path& images) {
  std::string why;
  auto need = [&](const fs::path& p) {
    if (!fs::exists(p)) why += (why.empty() ? "" : ", ") + p.string();
  };
  if (weights.empty()) why = "S4D_METRIC_WEIGHTS (not set)";
  else
    for (const std::string& w : c.weights) need(weights / w);
  if (images.empty()) why += (why.empty() ? "" : ", ") + std::string("S4D_CALIBRATION_DIR (not set)");
  else
    for (const std::string& i : kImages)
      for (const char* dir : {"ref_dir", "dist_dir"}) need(images / dir / (i + ".bmp"));
  return why;
}

}  // namespace

int main() {
  const fs::path weights = env_path("S4D_METRIC_WEIGHTS"), images = env_path("S4D_CALIBRATION_DIR");
  const std::vector<Calibration> calibrations = {
      {"dists", {"vgg16.safetensors", "dists.safetensors"}, {0.4742, 0.1424, 0.0682, 0.0287, 0.3123}},
      {"lpips_alex", {"alexnet.safetensors", "lpips_alex.safetensors"}, {0.7237, 0.2572, 0.0508, 0.0521, 0.4253}},
      {"ckdn", {"ckdn.safetensors"}, {0.2833, 0.5766, 0.6367, 0.6579, 0.5999}, kCkdnRelativeTolerance},
      {"musiq", {"musiq.safetensors"}, {12.4785, 75.7772, 73.7454, 75.4609, 38.0257}, kMusiqRelativeTolerance},
      {"musiq_paq2piq", {"musiq_paq2piq.safetensors"}, {46.0196, 72.6655, 73.7657, 74.3880, 69.7233}, kMusiqRelativeTolerance},
  };
  int ran = 0, failed = 0;
  try {
    std::unique_ptr<engine::Context> ctx;
    for (const Calibration& c : calibrations) {
      const std::string why = missing(c, weights, images);
      if (!why.empty()) {
        std::cout << c.metric << ": skipped: missing " << why << "\n";
        continue;
      }
      if (!ctx) ctx = std::make_unique<engine::Context>();
      std::function<double(const io::ImageF&, const io::ImageF&)> score;
      std::unique_ptr<metrics::Dists> dists;
      std::unique_ptr<metrics::Lpips> lpips;
      std::unique_ptr<metrics::Ckdn> ckdn;
      std::unique_ptr<metrics::Musiq> musiq;
      if (c.metric.rfind("musiq", 0) == 0) {
        musiq = std::make_unique<metrics::Musiq>(*ctx, io::SafetensorsFile(weights / c.weights[0]));
        score = [&](const io::ImageF& a, const io::ImageF&) { return (*musiq)(a); };
      } else if (c.metric == "ckdn") {
        ckdn = std::make_unique<metrics::Ckdn>(*ctx, io::SafetensorsFile(weights / c.weights[0]));
        score = [&](const io::ImageF& a, const io::ImageF& b) { return (*ckdn)(a, b); };
      } else if (c.metric == "dists") {
        dists = std::make_unique<metrics::Dists>(*ctx, io::SafetensorsFile(weights / c.weights[0]),
                                                 io::SafetensorsFile(weights / c.weights[1]));
        score = [&](const io::ImageF& a, const io::ImageF& b) { return (*dists)(a, b); };
      } else {
        lpips = std::make_unique<metrics::Lpips>(*ctx, io::SafetensorsFile(weights / c.weights[0]),
                                                 io::SafetensorsFile(weights / c.weights[1]), metrics::LpipsNet::alex);
        score = [&](const io::ImageF& a, const io::ImageF& b) { return (*lpips)(a, b); };
      }
      ++ran;
      for (size_t k = 0; k < kImages.size(); ++k) {
        const io::ImageF dist = io::read_image_rgb(images / "dist_dir" / (kImages[k] + ".bmp"));
        const io::ImageF ref = io::read_image_rgb(images / "ref_dir" / (kImages[k] + ".bmp"));
        const double value = score(dist, ref), error = std::abs(value - c.published[k]);
        const bool ok = c.relative_tolerance > 0 ? error <= c.relative_tolerance * c.published[k] : error <= kTolerance;
        failed += ok ? 0 : 1;
        std::printf("%s %s: %.9g, published %.4f, error %.1e %s\n", c.metric.c_str(), kImages[k].c_str(), value,
                    c.published[k], error, ok ? "ok" : "FAILED");
      }
    }
  } catch (const std::exception& e) {
    std::cout << "error: " << e.what() << "\n";
    return 1;
  }
  if (ran == 0) return 77;
  return failed == 0 ? 0 : 1;
}
