// The bridge tests' fake pyiqa (tests/bench/fake_pyiqa/pyiqa/__init__.py): where it is, how to put it
// on the bridge's PYTHONPATH, and its scores recomputed from the frames (8-bit levels / 255, as it
// decodes the PNGs), so a test checks that the numbers travel from pyiqa's calls to the report.
// S4D_SOURCE_DIR must be defined for the test target.
#pragma once
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "s4d/io/image_io.h"

namespace s4d::test {

inline std::filesystem::path fake_pyiqa_dir() { return std::filesystem::path(S4D_SOURCE_DIR) / "tests" / "bench" / "fake_pyiqa"; }

// Sets an environment variable for a scope (the bridge's process inherits it), restoring the old value.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// The fake on PYTHONPATH, with its failure directives (S4D_FAKE_PYIQA; "" for none), and DINO pointed
// at a folder without a hubconf.py, so dino_score fails on its own without reaching the network.
struct FakePyiqa {
  explicit FakePyiqa(const std::string& modes = "")
      : path("PYTHONPATH", fake_pyiqa_dir().string()), modes_env("S4D_FAKE_PYIQA", modes),
        dino("S4D_DINO_REPO", (fake_pyiqa_dir() / "no_dino_here").string()) {}
  ScopedEnv path, modes_env, dino;
};

// Mean of colour channel `c` (0..2), or of all three (-1), in double; an RGBA image's alpha is skipped
// as the fake skips it.
inline double channel_mean(const io::ImageF& im, int c = -1) {
  const size_t step = size_t(im.channels);
  double s = 0;
  size_t n = 0;
  for (size_t i = 0; i < im.data.size(); ++i)
    if (i % step < 3 && (c < 0 || int(i % step) == c)) s += im.data[i], ++n;
  return s / double(n);
}

// The fake's score for a bridge key: per frame (no-reference keys), the pair (dists: target, ref) or
// the frame against the style image (ckdn).
inline double fake_pyiqa_score(const std::string& key, const io::ImageF& target, const io::ImageF* ref = nullptr) {
  if (key == "clipiqa_plus") return channel_mean(target);
  if (key == "musiq") return 100 * channel_mean(target, 0);
  if (key == "musiq_paq2piq") return 100 * channel_mean(target, 1);
  if (key == "qalign") return 1 + 4 * channel_mean(target, 2);
  if (ref == nullptr) throw std::invalid_argument("fake_pyiqa_score: " + key + " needs a reference image");
  if (key == "ckdn") return 0.5 + (channel_mean(target) - channel_mean(*ref)) / 2;
  if (key != "dists" || ref->data.size() != target.data.size() || ref->channels != target.channels)
    throw std::invalid_argument("fake_pyiqa_score: no fake score for " + key + " on these images");
  const size_t step = size_t(target.channels);
  double d = 0;
  for (size_t i = 0; i < target.data.size(); ++i)
    if (i % step < 3) d += std::abs(double(target.data[i]) - ref->data[i]);
  return d / double(target.data.size() / step * 3);
}

}  // namespace s4d::test
