#include <stdexcept>

#include "s4d/metrics/flow.h"

namespace s4d::metrics {

Flow read_flow_exr(const std::filesystem::path& path) {
  const io::ExrImage exr = io::read_exr(path);
  Flow f{exr.width, exr.height, std::vector<float>(size_t(exr.width) * size_t(exr.height) * 2)};
  const char* names[2] = {"u", "v"};
  for (int c = 0; c < 2; ++c) {
    auto it = exr.channels.find(names[c]);
    if (it == exr.channels.end())
      throw std::runtime_error(path.string() + ": flow EXR has no channel '" + names[c] + "' (expected channels u and v, in pixels)");
    for (size_t i = 0; i < it->second.size(); ++i) f.uv[i * 2 + c] = it->second[i];
  }
  return f;
}

}  // namespace s4d::metrics
