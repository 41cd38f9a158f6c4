#include "bench_ground_truth.h"

#include <cmath>
#include <cstdio>

#include "s4d/data/frame_cache.h"
#include "s4d/io/image_io.h"

namespace s4d::cli {

std::optional<std::string> write_ground_truth(const data::Dataset& dataset, const std::vector<protocols::Sequence>& sequences,
                                              const std::filesystem::path& dir) {
  std::vector<std::vector<const data::View*>> matched;
  for (const protocols::Sequence& seq : sequences) {
    matched.emplace_back();
    for (const protocols::ProtocolFrame& f : seq.frames) {
      const data::View* hit = nullptr;
      for (const data::View& v : dataset.views)
        if (v.test && protocols::camera_name(v) == seq.name && std::abs(v.time - f.time) < 1e-9) hit = &v;
      if (!hit) {
        char time[32];
        std::snprintf(time, sizeof time, "%.6g", f.time);
        return "the dataset has no captured test view of " + seq.name + " at time " + time +
               " (a D-NeRF test view's pose is captured at its own time only), so the test protocol's renders have no "
               "ground truth";
      }
      matched.back().push_back(hit);
    }
  }
  data::FrameCache cache(dataset, size_t{64} << 20);
  for (size_t s = 0; s < sequences.size(); ++s) {
    std::filesystem::create_directories(dir / sequences[s].name);
    for (size_t k = 0; k < matched[s].size(); ++k) {
      char name[32];
      std::snprintf(name, sizeof name, "%04zu.png", k);
      io::write_png(dir / sequences[s].name / name, cache.get(*matched[s][k]));
    }
  }
  return std::nullopt;
}

}  // namespace s4d::cli
