// Trainer::Impl's growth into missed content: render a few training views, find where the render
// misses the ground truth (missing_content.h) and seed Gaussians there. In the fine stage a seed
// found at time t is placed where the deformation field carries it to the seen point at t
// (canonical = p - (deform(p, t) - p), one fixed-point step), so it moves with the field from its
// birth.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

#include "s4d/splat/scene_upload.h"
#include "s4d/train/missing_content.h"
#include "trainer_impl.h"

namespace s4d::train {

namespace {

constexpr float kShC0 = 0.28209479177387814f;  // Y_0^0: rgb = 0.5 + C0 * dc
constexpr float kSeedOpacity = 0.3f;           // visible at once, still easy to fade if wrong
constexpr size_t kNeighbours = 4;              // other views a plane sweep compares with
constexpr double kBoxMargin = 0.1;             // of the box's size, on each side

// The views nearest in time to `v` (other poses first at equal distance: a rig's same-time cameras).
std::vector<const data::View*> nearest_views(const data::View& v, const std::vector<const data::View*>& pool) {
  std::vector<const data::View*> out;
  for (const data::View* o : pool)
    if (o != &v && o->camera.world_to_cam != v.camera.world_to_cam) out.push_back(o);
  std::stable_sort(out.begin(), out.end(), [&](const data::View* a, const data::View* b) {
    return std::abs(a->time - v.time) < std::abs(b->time - v.time);
  });
  if (out.size() > kNeighbours) out.resize(kNeighbours);
  return out;
}

io::ImageF download_rgb(engine::Context& ctx, const splat::Rasterizer& r, const splat::Camera& cam) {
  const size_t n = size_t{cam.width} * cam.height;
  io::ImageF im{int(cam.width), int(cam.height), 3, ctx.download<float>(r.rgb(), n * 3)};
  for (float& v : im.data) v = std::clamp(v, 0.0f, 1.0f);
  return im;
}

}  // namespace

std::vector<const data::View*> Trainer::Impl::seed_pool() const {
  if (!fine()) return static_views;
  const double window = fine_window(), from = window < 1.0 ? window - config.fine_time_front : -1.0;
  std::vector<const data::View*> newest, open;
  for (const data::View* v : train_views) {
    if (v->time > window + 1e-9 && v->time > static_window() + 1e-9) continue;
    open.push_back(v);
    if (v->time >= from - 1e-9) newest.push_back(v);
  }
  return newest.empty() ? open : newest;
}

void Trainer::Impl::seed_missing_content(const std::string& when) {
  const uint32_t n = gaussians->size();
  if (config.seed_views == 0 || n >= config.budget) return;
  const std::vector<const data::View*> pool = seed_pool();
  if (pool.empty()) return;
  std::array<float, 3> lo = aabb_min, hi = aabb_max;
  for (size_t a = 0; a < 3; ++a) {
    const float m = static_cast<float>(kBoxMargin * (hi[a] - lo[a]));
    lo[a] -= m, hi[a] += m;
  }
  // Which views: a deterministic walk through the pool by densification round, so a resumed run
  // seeds from the same views.
  const uint64_t round = iteration / std::max<uint32_t>(1, config.densify_every) + (fine() ? 7919u : 0u);
  std::map<const data::View*, std::vector<Seed>> found;
  size_t total = 0;
  for (uint32_t j = 0; j < config.seed_views && total + n < config.budget; ++j) {
    const data::View& v = *pool[((round * config.seed_views + j) * 2654435761ull) % pool.size()];
    if (found.count(&v)) continue;
    const splat::Camera cam = splat::to_splat_camera(v.camera);
    rast.forward(fine() ? deform_to(v.time) : gaussians->params(active_degree()), cam, dataset.background);
    const io::ImageF rgb = download_rgb(ctx, rast, cam);
    const size_t pixels = size_t{cam.width} * cam.height;
    const std::vector<float> alpha = ctx.download<float>(rast.alpha(), pixels), depth = ctx.download<float>(rast.depth(), pixels);
    // The frame cache's references hold until its next get: the views are copied.
    std::vector<io::ImageF> images{frames.get(v)};
    const std::vector<const data::View*> near = nearest_views(v, train_views);
    for (const data::View* o : near) images.push_back(frames.get(*o));
    std::vector<ViewImage> others;
    for (size_t k = 0; k < near.size(); ++k) others.push_back({&images[k + 1], near[k]->camera});
    SeedSettings settings;
    settings.max_seeds = static_cast<uint32_t>(std::min<size_t>(settings.max_seeds, config.budget - n - total));
    std::vector<Seed> seeds = find_missing_content({&images[0], v.camera}, {&rgb, &alpha, &depth}, others, lo, hi, settings);
    total += seeds.size();
    if (!seeds.empty()) found[&v] = std::move(seeds);
  }
  if (total == 0) return;

  model::HostState state = gaussians->download();
  io::GaussianCloud& c = state.cloud;
  const size_t k = c.sh_coeffs();
  std::vector<std::pair<const data::View*, size_t>> groups;  // the view and its first seed's index
  for (const auto& [view, seeds] : found) {
    groups.emplace_back(view, c.size());
    for (const Seed& s : seeds) {
      c.means.insert(c.means.end(), s.position.begin(), s.position.end());
      const float log_s = std::log(std::max(s.scale, 1e-7f));
      c.log_scales.insert(c.log_scales.end(), {log_s, log_s, log_s});
      c.quats.insert(c.quats.end(), {1, 0, 0, 0});
      c.opacity_logits.push_back(std::log(kSeedOpacity / (1 - kSeedOpacity)));
      for (size_t q = 0; q < k; ++q)
        for (size_t ch = 0; ch < 3; ++ch) c.sh.push_back(q == 0 ? (s.colour[ch] - 0.5f) / kShC0 : 0.0f);
    }
  }
  const size_t m = c.size();
  for (splat::Attr a : splat::kCloudAttrs) {
    const size_t w = splat::attr_floats(a, static_cast<uint32_t>(k));
    state.m[a].resize(m * w, 0.0f), state.v[a].resize(m * w, 0.0f);
  }
  for (std::vector<float>& s : state.stats) s.resize(m, 0.0f);
  gaussians = std::make_unique<model::TrainableGaussians>(ctx, state, "gaussians");
  still_count = 0;  // every Gaussian is deformed again until the split is measured
  if (fine()) {
    for (size_t g = 0; g < groups.size(); ++g) {
      const size_t from = groups[g].second, to = g + 1 < groups.size() ? groups[g + 1].second : m;
      const splat::GaussianParams p = deform_to(groups[g].first->time);
      const std::vector<float> moved = ctx.download<float>(*p[splat::Attr::means], m * 3);
      for (size_t i = from * 3; i < to * 3; ++i) c.means[i] = 2 * c.means[i] - moved[i];
    }
    gaussians = std::make_unique<model::TrainableGaussians>(ctx, state, "gaussians");
  }
  densify_log.push_back({{"stage", run::stage_name(stage)}, {"iteration", iteration}, {"event", "seed"},
                         {"before", n}, {"seeded", total}, {"views", found.size()}, {"after", m}});
  if (total * 10 > n) std::cerr << "densify (" << when << "): seeded " << total << " Gaussians where " << found.size()
                                << " training views miss content (" << n << " -> " << m << ")\n";
}

}  // namespace s4d::train
