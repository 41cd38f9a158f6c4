#include "s4d/train/divergence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "s4d/model/checkpoint.h"

namespace s4d::train {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool out_of_range(float x, float limit, bool log_scale) {
  return !std::isfinite(x) || std::fabs(x) > (log_scale && x > 0 ? kLogScaleLimit : limit);
}

// The worst of the bad values: NaN, then inf, then the largest magnitude.
struct Worst {
  bool nan = false, inf = false;
  float largest = 0;
  void add(float x) {
    if (std::isnan(x)) nan = true;
    else if (std::isinf(x)) inf = true;
    else largest = std::max(largest, std::fabs(x));
  }
  std::string text() const {
    if (nan) return "NaN";
    if (inf) return "inf";
    char s[32];
    std::snprintf(s, sizeof s, "up to %.3g", double(largest));
    return s;
  }
};

}  // namespace

float range_limit(const std::string& array) { return ends_with(array, ".adam_v") ? kSecondMomentLimit : kRangeLimit; }

uint32_t local_limit(uint32_t gaussians) { return std::max<uint32_t>(16, gaussians / 100); }

Divergence find_divergence(const model::Checkpoint& state, const PartName& part, uint32_t extra_rows) {
  const model::HostState& s = state.state;
  const size_t n = extra_rows > 0 ? extra_rows : s.cloud.size();
  std::vector<std::string> found;
  std::set<uint32_t> rows;
  bool global = false;

  auto per_gaussian = [&](const std::string& name, const std::vector<float>& values) {
    if (n == 0 || values.empty()) return;
    const size_t width = values.size() / n;
    const bool log_scale = name == splat::attr_name(splat::Attr::log_scales);
    const float limit = range_limit(name);
    Worst worst;
    size_t bad = 0, first = n;
    for (size_t g = 0; g < n; ++g) {
      bool hit = false;
      for (size_t k = 0; k < width; ++k) {
        const float x = values[g * width + k];
        if (out_of_range(x, limit, log_scale)) worst.add(x), hit = true;
      }
      if (!hit) continue;
      ++bad, first = std::min(first, g);
      rows.insert(static_cast<uint32_t>(g));
    }
    if (bad > 0)
      found.push_back("'" + name + "' of " + std::to_string(bad) + (bad == 1 ? " Gaussian (" : " Gaussians (") +
                      worst.text() + "; first Gaussian " + std::to_string(first) + ")");
  };
  auto whole = [&](const std::string& name, const std::vector<float>& values) {
    const float limit = range_limit(name);
    Worst worst;
    size_t bad = 0;
    std::vector<std::string> parts;
    for (size_t i = 0; i < values.size(); ++i) {
      if (!out_of_range(values[i], limit, false)) continue;
      worst.add(values[i]), ++bad;
      if (!part) continue;
      const std::string p = part(name, i);
      if (std::find(parts.begin(), parts.end(), p) == parts.end()) parts.push_back(p);
    }
    if (bad == 0) return;
    global = true;
    std::string where;
    for (size_t k = 0; k < parts.size() && k < 3; ++k) where += (k ? ", " : "; in ") + parts[k];
    if (parts.size() > 3) where += " and " + std::to_string(parts.size() - 3) + " more";
    found.push_back("'" + name + "' at " + std::to_string(bad) + (bad == 1 ? " entry (" : " entries (") + worst.text() +
                    where + ")");
  };

  const auto cloud = splat::cloud_arrays(s.cloud);
  for (splat::Attr a : splat::kCloudAttrs) {
    const std::string name = splat::attr_name(a);
    per_gaussian(name, *cloud[a]);
    per_gaussian(name + ".adam_m", s.m[a]);
    per_gaussian(name + ".adam_v", s.v[a]);
  }
  for (uint32_t k = 0; k < model::kStatCount; ++k) per_gaussian(model::stat_name(model::Stat(k)), s.stats[k]);
  for (const auto& [name, values] : state.extra) {
    if (ends_with(name, "mask")) continue;
    if (extra_rows > 0 && values.size() % extra_rows == 0) per_gaussian(name, values);
    else whole(name, values);
  }

  Divergence d;
  if (found.empty()) return d;
  d.where = "out of range: ";
  for (size_t k = 0; k < found.size() && k < 4; ++k) d.where += (k ? "; " : "") + found[k];
  if (found.size() > 4) d.where += "; and " + std::to_string(found.size() - 4) + " more arrays";
  d.gaussians.assign(rows.begin(), rows.end());
  d.local = !global && d.gaussians.size() <= local_limit(static_cast<uint32_t>(n));
  return d;
}

}  // namespace s4d::train
