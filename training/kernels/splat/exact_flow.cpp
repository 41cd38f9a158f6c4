// Host side of the exact-flow kernels (shaders/flow): one dispatch each, one thread per Gaussian.
#include "s4d/splat/exact_flow.h"

#include <stdexcept>
#include <string>

#include "gpu_camera.h"
#include "s4d/engine/recorder.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d_flow.h"

namespace s4d::splat {
namespace {

using primitives::ceil_div;
using primitives::shader_pipeline;

void require(const engine::Buffer* b, const char* what, size_t bytes) {
  if (b == nullptr) throw std::invalid_argument(std::string("exact flow: ") + what + " buffer is missing");
  if (b->size() < bytes)
    throw std::invalid_argument("exact flow: buffer '" + b->name() + "' (" + what + ") holds " + std::to_string(b->size()) +
                                " bytes, " + std::to_string(bytes) + " needed");
}

constexpr size_t kLaneBytes = S4D_FLOW_SCREEN_STRIDE * sizeof(float);

}  // namespace

void project_means(engine::Context& ctx, const GaussianParams& g, const Camera& cam, engine::Buffer& screen) {
  require(g[Attr::means], "means", size_t{g.count} * 12);
  require(&screen, "screen lanes", size_t{g.count} * kLaneBytes);
  if (g.count == 0) return;
  const gpu::FlowProjectParams p{.cam = gpu_camera(cam), .n = g.count, ._pad0 = 0, ._pad1 = 0, ._pad2 = 0};
  engine::Recorder rec(ctx, "flow project");
  rec.dispatch(shader_pipeline(ctx, shaders::Id::flow_project),
               {S4D_BIND(FLOWP_MEANS, *g[Attr::means]), S4D_BIND(FLOWP_SCREEN, screen)}, p, ceil_div(g.count, S4D_FLOW_WG));
  ctx.run(std::move(rec));
}

void screen_displacement(engine::Context& ctx, const engine::Buffer& from, const engine::Buffer& to, uint32_t n,
                         engine::Buffer& colors) {
  require(&from, "screen lanes (from)", size_t{n} * kLaneBytes);
  require(&to, "screen lanes (to)", size_t{n} * kLaneBytes);
  require(&colors, "displacement colours", size_t{n} * 12);
  if (n == 0) return;
  const gpu::FlowDisplaceParams p{.n = n, ._pad0 = 0, ._pad1 = 0, ._pad2 = 0};
  engine::Recorder rec(ctx, "flow displace");
  rec.dispatch(shader_pipeline(ctx, shaders::Id::flow_displace),
               {S4D_BIND(FLOWD_FROM, from), S4D_BIND(FLOWD_TO, to), S4D_BIND(FLOWD_COLORS, colors)}, p,
               ceil_div(n, S4D_FLOW_WG));
  ctx.run(std::move(rec));
}

FlowImage render_flow(Rasterizer& r, GaussianParams g, const engine::Buffer& displacement, const Camera& cam) {
  g[Attr::colors] = &displacement;
  r.forward(g, cam, {0.0f, 0.0f, 0.0f});  // a black background adds nothing to the blended sum
  const size_t npix = size_t{cam.width} * cam.height;
  const std::vector<float> sum = r.context().download<float>(r.rgb(), 3 * npix);
  const std::vector<float> alpha = r.context().download<float>(r.alpha(), npix);
  FlowImage f{cam.width, cam.height, std::vector<float>(npix, 0.0f), std::vector<float>(npix, 0.0f)};
  for (size_t k = 0; k < npix; ++k) {
    if (!(alpha[k] > 1e-6f)) continue;
    f.u[k] = sum[3 * k] / alpha[k];
    f.v[k] = sum[3 * k + 1] / alpha[k];
  }
  return f;
}

}  // namespace s4d::splat
