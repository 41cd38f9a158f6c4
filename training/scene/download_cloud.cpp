#include "s4d/scene/download_cloud.h"

#include <stdexcept>

namespace s4d::scene {

io::GaussianCloud download_cloud(engine::Context& ctx, const splat::GaussianParams& g) {
  if (g.colors) throw std::invalid_argument("download_cloud: the Gaussians have a colour buffer in place of SH");
  const size_t n = g.count;
  io::GaussianCloud cloud;
  cloud.means = ctx.download<float>(*g.means, n * 3);
  cloud.log_scales = ctx.download<float>(*g.log_scales, n * 3);
  cloud.quats = ctx.download<float>(*g.quats, n * 4);
  cloud.opacity_logits = ctx.download<float>(*g.opacity_logits, n);
  cloud.sh_degree = static_cast<int>(g.sh_degree);
  const size_t stored = g.sh_coeffs, kept = cloud.sh_coeffs();
  const std::vector<float> sh = ctx.download<float>(*g.sh, n * stored * 3);
  cloud.sh.reserve(n * kept * 3);
  for (size_t i = 0; i < n; ++i)
    cloud.sh.insert(cloud.sh.end(), sh.begin() + static_cast<std::ptrdiff_t>(i * stored * 3),
                    sh.begin() + static_cast<std::ptrdiff_t>((i * stored + kept) * 3));
  return cloud;
}

}  // namespace s4d::scene
