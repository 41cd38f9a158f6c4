#include "s4d/scene/download_cloud.h"

#include <stdexcept>

#include "s4d/io/half_float.h"

namespace s4d::scene {

io::GaussianCloud download_cloud(engine::Context& ctx, const splat::GaussianParams& g) {
  using splat::Attr;
  if (g[Attr::colors]) throw std::invalid_argument("download_cloud: the Gaussians have a colour buffer in place of SH");
  const size_t n = g.count;
  io::GaussianCloud cloud;
  const auto arrays = splat::cloud_arrays(cloud);
  for (Attr a : {Attr::means, Attr::log_scales, Attr::quats, Attr::opacity_logits})
    *arrays[a] = ctx.download<float>(*g[a], n * splat::attr_floats(a, 0));
  cloud.sh_degree = static_cast<int>(g.sh_degree);
  const size_t stored = g.sh_coeffs, kept = cloud.sh_coeffs();
  const std::vector<float> sh = g.sh_storage == splat::Storage::f16
                                    ? io::unpack_halves(ctx.download<uint32_t>(*g[Attr::sh], g.bytes(Attr::sh) / 4), n * stored * 3)
                                    : ctx.download<float>(*g[Attr::sh], n * stored * 3);
  cloud.sh.reserve(n * kept * 3);
  for (size_t i = 0; i < n; ++i)
    cloud.sh.insert(cloud.sh.end(), sh.begin() + static_cast<std::ptrdiff_t>(i * stored * 3),
                    sh.begin() + static_cast<std::ptrdiff_t>((i * stored + kept) * 3));
  return cloud;
}

}  // namespace s4d::scene
