// Host side of the rasterizer: buffer management and the order of kernels (ALGORITHMS.md 1.3-1.6).
#include "s4d/splat/rasterizer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "s4d/engine/device_info.h"
#include "s4d/engine/recorder.h"
#include "s4d/engine/stage_timer.h"
#include "s4d/primitives/iota.h"
#include "s4d/primitives/scan.h"
#include "s4d/primitives/shader_pipeline.h"
#include "gpu_camera.h"
#include "s4d_splat.h"
#include "style_raster.h"

namespace s4d::splat {
namespace {

using primitives::ceil_div;
using primitives::shader_pipeline;

// Grown buffers get headroom so a slowly growing count does not reallocate every call.
uint32_t grown(uint32_t needed) { return needed + needed / 4 + 1024; }

void require(const engine::Buffer* b, const char* what, size_t bytes) {
  if (b == nullptr) throw std::invalid_argument(std::string("rasterizer: ") + what + " buffer is missing");
  if (b->size() < bytes)
    throw std::invalid_argument("rasterizer: buffer '" + b->name() + "' (" + what + ") holds " +
                                std::to_string(b->size()) + " bytes, " + std::to_string(bytes) + " needed");
}

// The attributes a forward reads: the geometry and opacity, then colours or SH, then the style MLPs.
std::vector<Attr> read_attrs(bool colors, bool style) {
  std::vector<Attr> attrs = {Attr::means, Attr::log_scales, Attr::quats, Attr::opacity_logits,
                             colors ? Attr::colors : Attr::sh};
  if (style) attrs.push_back(Attr::style_mlp);
  return attrs;
}

void check_params(const GaussianParams& g) {
  if (g.sh_degree > S4D_MAX_SH_DEGREE)
    throw std::invalid_argument("rasterizer: sh_degree " + std::to_string(g.sh_degree) + " is above 3");
  if (g.sh_coeffs < (g.sh_degree + 1) * (g.sh_degree + 1) || g.sh_coeffs > S4D_MAX_SH_COEFFS)
    throw std::invalid_argument("rasterizer: sh_coeffs " + std::to_string(g.sh_coeffs) + " does not hold degree " +
                                std::to_string(g.sh_degree));
  for (Attr a : read_attrs(g[Attr::colors] != nullptr, g.style != nullptr))
    require(g[a], attr_name(a), g.bytes(a));
}

void check_camera(const Camera& cam) {
  if (cam.width == 0 || cam.height == 0)
    throw std::invalid_argument("rasterizer: camera size " + std::to_string(cam.width) + "x" +
                                std::to_string(cam.height) + " is empty");
  // Tile rectangles pack each corner coordinate into 16 bits.
  if (ceil_div(cam.width, S4D_TILE_SIZE) > 0xFFFF || ceil_div(cam.height, S4D_TILE_SIZE) > 0xFFFF)
    throw std::invalid_argument("rasterizer: camera size " + std::to_string(cam.width) + "x" +
                                std::to_string(cam.height) + " exceeds 65535 tiles per axis");
  for (float v : cam.world_to_cam)
    if (!std::isfinite(v)) throw std::invalid_argument("rasterizer: camera pose is not finite");
  if (!(cam.fx > 0) || !(cam.fy > 0) || !std::isfinite(cam.fx) || !std::isfinite(cam.fy) || !std::isfinite(cam.cx) ||
      !std::isfinite(cam.cy))
    throw std::invalid_argument("rasterizer: camera intrinsics must be finite with positive focal lengths");
}

gpu::ProjectParams project_params(const GaussianParams& g, const Camera& cam) {
  gpu::ProjectParams p{};
  p.cam = gpu_camera(cam);
  p.n = g.count;
  p.sh_degree = g.sh_degree;
  p.sh_coeffs = g.sh_coeffs;
  p.flags = g[Attr::colors] != nullptr ? S4D_SPLAT_USE_COLORS : 0u;
  return p;
}

// llvmpipe ends any invocation after 65535 loop iterations in total (Mesa's
// LP_MAX_TGSI_LOOP_ITERATIONS), silently; the blend loops are unrolled so this allows long lists,
// and longer ones are refused rather than rendered wrong. The style kernels' smaller batches and
// 62 atomics per entry give them their own limits (s4d_style_splat.h).
void check_list_length(const engine::DeviceInfo& info, uint32_t longest, bool style, bool cas, const char* pass) {
  if (info.driver_name != "llvmpipe") return;
  const uint32_t limit = style ? (cas ? S4D_LLVMPIPE_MAX_STYLE_LIST_CAS : S4D_LLVMPIPE_MAX_STYLE_LIST)
                               : (cas ? S4D_LLVMPIPE_MAX_TILE_LIST_CAS : S4D_LLVMPIPE_MAX_TILE_LIST);
  if (longest > limit)
    throw std::runtime_error(std::string("rasterizer: a tile holds ") + std::to_string(longest) +
                             " Gaussians, more than lavapipe can " + pass + " correctly (" + std::to_string(limit) +
                             ": llvmpipe stops shader loops after 65535 iterations); use fewer or smaller "
                             "Gaussians, or a GPU");
}

// A pixels-per-invocation option: 0 (by device) or one of the two variants.
void check_pixels(const std::string& name, const char* option, uint32_t value, uint32_t cpu, uint32_t gpu) {
  if (value != 0 && value != cpu && value != gpu)
    throw std::invalid_argument("rasterizer '" + name + "': " + option + " " + std::to_string(value) +
                                " is not 0 (by device), " + std::to_string(gpu) + " or " + std::to_string(cpu));
}

}  // namespace

Rasterizer::Rasterizer(engine::Context& ctx, std::string name, RasterizerOptions options)
    : ctx_(&ctx), name_(std::move(name)), options_(options) {
  check_pixels(name_, "backward_pixels", options.backward_pixels, S4D_RBWD_PIXELS_CPU, S4D_RBWD_PIXELS_GPU);
  check_pixels(name_, "forward_pixels", options.forward_pixels, S4D_RFWD_PIXELS_CPU, S4D_RFWD_PIXELS_GPU);
  const uint32_t lanes = options.min_subgroup_lanes;
  if (lanes != 0 && (!std::has_single_bit(lanes) || lanes > ctx.info().min_subgroup_size))
    throw std::invalid_argument("rasterizer '" + name_ + "': min_subgroup_lanes " + std::to_string(lanes) +
                                " is not 0 (the device's) or a power of two up to the device's " +
                                std::to_string(ctx.info().min_subgroup_size));
  reserve_gaussians(1);
  allocate_instances(std::max(1u, options.initial_instance_capacity));
  reserve_pixels(1, 1);
  list_stats_ = buffer("tile list stats", 4);
  totals_ = buffer("instance totals", 12);
  args_ = buffer("instance args", sizeof(gpu::InstanceArgs));
  readback_ = engine::Buffer(ctx, name_ + " readback", sizeof(Readback), engine::BufferKind::staging);
}

uint32_t Rasterizer::pixels_by_device(uint32_t forced, uint32_t cpu, uint32_t gpu) const {
  if (forced != 0) return forced;
  return ctx_->info().type == VK_PHYSICAL_DEVICE_TYPE_CPU ? cpu : gpu;
}

uint32_t Rasterizer::forward_pixels() const {
  return pixels_by_device(options_.forward_pixels, S4D_RFWD_PIXELS_CPU, S4D_RFWD_PIXELS_GPU);
}

uint32_t Rasterizer::backward_pixels() const {
  return pixels_by_device(options_.backward_pixels, S4D_RBWD_PIXELS_CPU, S4D_RBWD_PIXELS_GPU);
}

size_t Rasterizer::device_bytes() const {
  size_t total = 0;
  for (const engine::Buffer* b : {&xy_, &conic_opacity_, &color_depth_, &info_, &depth_keys_, &tiles_touched_,
                                  &sorted_ids_, &offsets_, &tile_keys_, &gaussian_ids_, &ranges_, &rgb_, &alpha_,
                                  &depth_, &count_, &last_, &final_t_, &grad2d_, &scan_scratch_, &list_stats_,
                                  &quadric_, &args_})
    total += b->size();
  for (const primitives::RadixSortScratch* s : {&depth_sort_, &tile_sort_})
    total += s->temp_keys.size() + s->temp_values.size() + s->histogram.size() + s->scan_scratch.size();
  return total;
}

engine::Buffer Rasterizer::buffer(const char* what, size_t bytes) const {
  return engine::Buffer(*ctx_, name_ + " " + what, bytes);
}

void Rasterizer::reserve_gaussians(uint32_t n) {
  if (n <= gaussian_capacity_ && xy_.valid()) return;
  const uint32_t cap = grown(n);
  const size_t c = cap;
  xy_ = buffer("xy", c * 8);
  conic_opacity_ = buffer("conic_opacity", c * 16);
  color_depth_ = buffer("color_depth", c * 16);
  info_ = buffer("info", c * 16);
  depth_keys_ = buffer("depth keys", c * 4);
  tiles_touched_ = buffer("tiles touched", c * 4);
  sorted_ids_ = buffer("depth order", c * 4);
  offsets_ = buffer("instance offsets", (c + 1) * 4);
  grad2d_ = buffer("grad2d", c * S4D_G2D_STRIDE * 4);
  scan_scratch_ = buffer("offsets scan scratch", primitives::scan_scratch_bytes(cap + 1));
  depth_sort_ = primitives::RadixSortScratch(*ctx_, cap, name_ + " depth sort");
  gaussian_capacity_ = cap;
}

void Rasterizer::reserve_quadrics(uint32_t n) {
  if (n <= quadric_capacity_ && quadric_.valid()) return;
  const uint32_t cap = grown(n);
  quadric_ = buffer("style quadric", size_t{cap} * S4D_STYLE_QUADRIC_STRIDE * 4);
  quadric_capacity_ = cap;
}

void Rasterizer::reserve_instances(uint32_t n) {
  if (n <= instance_capacity_ && tile_keys_.valid()) return;
  // Keys, values and the sort's two temporaries are one u32 per instance each.
  const uint64_t limit = ctx_->info().max_storage_buffer_range / 4;
  if (n > limit)
    throw std::invalid_argument("rasterizer: " + std::to_string(n) + " tile instances exceed what one buffer of " +
                                ctx_->info().name + " can hold (" + std::to_string(limit) +
                                "); lower the resolution or the number of Gaussians");
  allocate_instances(static_cast<uint32_t>(std::min<uint64_t>(grown(n), limit)));
}

void Rasterizer::allocate_instances(uint32_t cap) {
  tile_keys_ = buffer("tile keys", size_t{cap} * 4);
  gaussian_ids_ = buffer("instance ids", size_t{cap} * 4);
  tile_sort_ = primitives::RadixSortScratch(*ctx_, cap, name_ + " tile sort");
  instance_capacity_ = cap;
}

void Rasterizer::reserve_pixels(uint32_t width, uint32_t height) {
  const uint32_t pixels = width * height;
  const uint32_t tiles = ceil_div(width, S4D_TILE_SIZE) * ceil_div(height, S4D_TILE_SIZE);
  if (pixels <= pixel_capacity_ && tiles <= tile_capacity_ && rgb_.valid()) return;
  const size_t p = std::max(pixels, pixel_capacity_), t = std::max(tiles, tile_capacity_);
  rgb_ = buffer("rgb", p * 12);
  alpha_ = buffer("alpha", p * 4);
  depth_ = buffer("depth", p * 4);
  count_ = buffer("contributors", p * 4);
  last_ = buffer("last contributor", p * 4);
  final_t_ = buffer("final transmittance", p * 4);
  ranges_ = buffer("tile ranges", t * 8);
  pixel_capacity_ = static_cast<uint32_t>(p);
  tile_capacity_ = static_cast<uint32_t>(t);
}

void Rasterizer::record_forward(engine::Recorder& rec, const GaussianParams& g, const Camera& cam,
                                const std::array<float, 3>& background) {
  have_forward_ = false;  // until finish_forward: a failed forward leaves nothing to differentiate
  pending_ = false;
  check_params(g);
  check_camera(cam);
  if (g.style != nullptr) check_style(*g.style);
  if (uint64_t{cam.width} * cam.height * 12 > ctx_->info().max_storage_buffer_range)
    throw std::invalid_argument("rasterizer: a " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                                " RGB image exceeds the storage-buffer range of " + ctx_->info().name);
  const uint32_t n = g.count;
  reserve_gaussians(n);
  reserve_pixels(cam.width, cam.height);
  if (g.style != nullptr) reserve_quadrics(n);
  const gpu::ProjectParams pp = project_params(g, cam);
  const uint32_t tiles_x = pp.cam.size.z, num_tiles = pp.cam.size.z * pp.cam.size.w;
  const engine::Buffer& colors = g[Attr::colors] != nullptr ? *g[Attr::colors] : *g[Attr::sh];

  // Project, sort by depth, count tiles in depth order, scan to offsets.
  std::optional<engine::StageScope> stage(std::in_place, *ctx_, "project");
  const bool sh_half = g[Attr::colors] == nullptr && g.sh_storage == Storage::f16;
  rec.dispatch(
      shader_pipeline(*ctx_, sh_half ? shaders::Id::project_fwd_half : shaders::Id::project_fwd),
      {S4D_BIND(PROJ_MEANS, *g[Attr::means]), S4D_BIND(PROJ_LOG_SCALES, *g[Attr::log_scales]), S4D_BIND(PROJ_QUATS, *g[Attr::quats]),
       S4D_BIND(PROJ_OPACITY_LOGITS, *g[Attr::opacity_logits]), S4D_BIND(PROJ_SH, g[Attr::sh] ? *g[Attr::sh] : colors),
       S4D_BIND(PROJ_COLORS, colors), S4D_BIND(PROJ_XY, xy_), S4D_BIND(PROJ_CONIC_OPACITY, conic_opacity_),
       S4D_BIND(PROJ_COLOR_DEPTH, color_depth_), S4D_BIND(PROJ_INFO, info_), S4D_BIND(PROJ_DEPTH_KEYS, depth_keys_),
       S4D_BIND(PROJ_TILES_TOUCHED, tiles_touched_)},
      pp, ceil_div(n, S4D_SPLAT_WG));
  if (g.style != nullptr)
    rec.dispatch(shader_pipeline(*ctx_, shaders::Id::style_quadric),
                 {S4D_BIND(SQUAD_MEANS, *g[Attr::means]), S4D_BIND(SQUAD_LOG_SCALES, *g[Attr::log_scales]),
                  S4D_BIND(SQUAD_QUATS, *g[Attr::quats]), S4D_BIND(SQUAD_QUADRIC, quadric_)},
                 pp, ceil_div(n, S4D_SPLAT_WG));
  stage.emplace(*ctx_, "sort");
  primitives::cmd_iota(rec, sorted_ids_, n);
  rec.barrier();
  primitives::cmd_radix_sort(rec, depth_keys_, sorted_ids_, n, 32, depth_sort_);
  rec.fill(totals_, 0);
  rec.barrier();
  const gpu::BinningParams bp{.n = n, .tiles_x = tiles_x, .capacity = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::count_tiles),
               {S4D_BIND(COUNT_SORTED_IDS, sorted_ids_), S4D_BIND(COUNT_TILES_TOUCHED, tiles_touched_),
                S4D_BIND(COUNT_OFFSETS, offsets_), S4D_BIND(COUNT_TOTALS, totals_)},
               bp, ceil_div(uint64_t{n} + 1, S4D_SPLAT_WG));
  rec.barrier();
  primitives::cmd_exclusive_scan(rec, offsets_, n + 1, scan_scratch_);
  rec.barrier();

  // The instance count stays on the device: instance_args turns it into the live count (at most
  // the capacity) and the indirect dispatches over it; finish_forward reads it after the frame.
  const uint32_t cap = instance_capacity_;
  const uint32_t max_x = ctx_->max_groups_x() ? std::min(ctx_->max_groups_x(), ctx_->info().max_workgroup_count[0])
                                              : ctx_->info().max_workgroup_count[0];
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::instance_args),
               {S4D_BIND(ARGS_OFFSETS, offsets_), S4D_BIND(ARGS_OUT, args_)},
               gpu::InstanceArgsParams{.n = n, .capacity = cap, .max_groups_x = max_x, ._pad0 = 0}, 1);
  // Emit instances, sort them by tile (stable: depth order survives), find each tile's range, blend.
  rec.fill(ranges_, 0, size_t{num_tiles} * 8);
  const gpu::BinningParams ep{.n = n, .tiles_x = tiles_x, .capacity = cap, ._pad1 = 0};
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::emit_instances),
               {S4D_BIND(EMIT_SORTED_IDS, sorted_ids_), S4D_BIND(EMIT_OFFSETS, offsets_), S4D_BIND(EMIT_INFO, info_),
                S4D_BIND(EMIT_TILE_KEYS, tile_keys_), S4D_BIND(EMIT_GAUSSIAN_IDS, gaussian_ids_)},
               ep, ceil_div(n, S4D_SPLAT_WG));
  rec.barrier();
  const uint32_t tile_bits = std::max(1u, static_cast<uint32_t>(std::bit_width(num_tiles - 1)));
  primitives::cmd_radix_sort(
      rec, tile_keys_, gaussian_ids_,
      primitives::LiveCount{.count = args_, .groups = args_, .groups_offset = S4D_INSTANCE_ARGS_SORT_OFFSET, .bound = cap},
      tile_bits, tile_sort_);
  rec.barrier();
  const gpu::BinningParams rp{.n = cap, .tiles_x = tiles_x, .capacity = 0, ._pad1 = 0};
  rec.dispatch_indirect(shader_pipeline(*ctx_, shaders::Id::tile_ranges),
                        {S4D_BIND(RANGES_TILE_KEYS, tile_keys_), S4D_BIND(RANGES_OUT, ranges_),
                         S4D_BIND(RANGES_LIVE, args_)},
                        rp, args_, S4D_INSTANCE_ARGS_RANGES_OFFSET);
  rec.barrier();
  rec.fill(list_stats_, 0);
  rec.barrier();
  const gpu::BinningParams sp{.n = num_tiles, .tiles_x = tiles_x, .capacity = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::tile_list_stats),
               {S4D_BIND(LIST_STATS_RANGES, ranges_), S4D_BIND(LIST_STATS_OUT, list_stats_)}, sp,
               ceil_div(num_tiles, S4D_SPLAT_WG));
  rec.barrier();
  // What finish_forward checks, into host-visible memory in this submission: no read-back of its own.
  rec.copy(totals_, readback_, sizeof(Readback::totals), 0, offsetof(Readback, totals));
  rec.copy(list_stats_, readback_, sizeof(Readback::longest), 0, offsetof(Readback, longest));
  stage.emplace(*ctx_, "raster");
  std::vector<engine::Binding> bind = {
      S4D_BIND(RASTER_RANGES, ranges_),      S4D_BIND(RASTER_GAUSSIAN_IDS, gaussian_ids_),
      S4D_BIND(RASTER_XY, xy_),              S4D_BIND(RASTER_CONIC_OPACITY, conic_opacity_),
      S4D_BIND(RASTER_COLOR_DEPTH, color_depth_), S4D_BIND(RASTER_RGB, rgb_),
      S4D_BIND(RASTER_ALPHA, alpha_),        S4D_BIND(RASTER_DEPTH, depth_),
      S4D_BIND(RASTER_COUNT, count_),        S4D_BIND(RASTER_LAST, last_),
      S4D_BIND(RASTER_FINAL_T, final_t_)};
  if (g.style != nullptr)
    bind.insert(bind.end(), {S4D_BIND(RASTER_QUADRIC, quadric_), S4D_BIND(RASTER_STYLE_MLP, *g[Attr::style_mlp])});
  const gpu::RasterParams raster = raster_params(g.style, pp.cam, background, 0u);
  using shaders::Id;
  const bool mlp_half = g.style_mlp_storage == Storage::f16;
  const Id style_id = forward_pixels() == 1 ? (mlp_half ? Id::style_raster_fwd_px1_half : Id::style_raster_fwd_px1)
                                            : (mlp_half ? Id::style_raster_fwd_half : Id::style_raster_fwd);
  const Id id = g.style != nullptr ? style_id : forward_pixels() == 1 ? Id::raster_fwd_px1 : Id::raster_fwd;
  rec.dispatch_raw(shader_pipeline(*ctx_, id), bind, &raster, sizeof raster, num_tiles);

  cam_ = cam;
  background_ = background;
  count_last_ = n;
  colors_last_ = g[Attr::colors] != nullptr;
  sh_degree_last_ = g.sh_degree;
  sh_coeffs_last_ = g.sh_coeffs;
  style_last_ = g.style != nullptr;
  if (style_last_) style_settings_last_ = *g.style;
  pending_ = true;
}

std::optional<RenderStats> Rasterizer::finish_forward() {
  if (!pending_) throw std::logic_error("rasterizer: finish_forward() without a recorded forward");
  pending_ = false;
  Readback back;
  std::memcpy(&back, readback_.mapped(), sizeof back);
  const uint32_t* totals = back.totals;
  if (totals[1] != 0)
    throw std::invalid_argument("rasterizer: the Gaussians cover more than 2^32 tile instances in this view; lower the "
                                "resolution or the number or size of the Gaussians");
  // emit_instances loops over one Gaussian's rectangle: keep it inside llvmpipe's loop cap.
  if (ctx_->info().driver_name == "llvmpipe" &&
      uint64_t{totals[2]} + ceil_div(cam_.height, S4D_TILE_SIZE) > 65000)
    throw std::invalid_argument("rasterizer: one Gaussian covers " + std::to_string(totals[2]) +
                                " tiles, more than lavapipe's 65535-iteration shader loops can emit");
  const uint32_t instances = totals[0];
  if (instances > instance_capacity_) {  // emit dropped the instances past the capacity
    reserve_instances(instances);
    ++overflows_;
    return std::nullopt;
  }
  const RenderStats stats{.instances = instances, .longest_tile_list = back.longest};
  check_list_length(ctx_->info(), stats.longest_tile_list, style_last_, false, "blend");
  longest_last_ = stats.longest_tile_list;
  have_forward_ = true;
  return stats;
}

RenderStats Rasterizer::forward(const GaussianParams& g, const Camera& cam, const std::array<float, 3>& background) {
  for (;;) {  // twice at most: an overflow grows the instance buffers past the count it read
    engine::Recorder rec(*ctx_, name_ + " forward");
    record_forward(rec, g, cam, background);
    ctx_->run(std::move(rec));
    if (const std::optional<RenderStats> stats = finish_forward()) return *stats;
  }
}

void Rasterizer::backward(const GaussianParams& g, const ImageCotangents& v, const GaussianGrads& out) {
  engine::Recorder rec(*ctx_, name_ + " backward");
  record_backward(rec, g, v, out);
  ctx_->run(std::move(rec));
}

void Rasterizer::record_backward(engine::Recorder& rec, const GaussianParams& g, const ImageCotangents& v,
                                 const GaussianGrads& out) {
  if (!have_forward_) throw std::logic_error("rasterizer: backward() called before forward()");
  if (g.sh_storage != Storage::f32 || g.style_mlp_storage != Storage::f32)
    throw std::invalid_argument("rasterizer: backward() needs float sh and style_mlp; half storage renders only");
  check_params(g);
  if (g.count != count_last_ || (g[Attr::colors] != nullptr) != colors_last_ || g.sh_degree != sh_degree_last_ ||
      g.sh_coeffs != sh_coeffs_last_ || (g.style != nullptr) != style_last_ ||
      (style_last_ && !same_style_settings(*g.style, style_settings_last_)))
    throw std::invalid_argument("rasterizer: backward() parameters differ from the last forward()");
  if (style_last_) check_style(*g.style);
  const uint32_t n = g.count;
  const size_t pixels = size_t{cam_.width} * cam_.height;
  require(v.v_rgb, "v_rgb", pixels * 12);
  if (v.v_alpha) require(v.v_alpha, "v_alpha", pixels * 4);
  if (v.v_depth) require(v.v_depth, "v_depth", pixels * 4);
  for (Attr a : read_attrs(colors_last_, style_last_))
    require(out[a], ("v_" + std::string(attr_name(a))).c_str(), size_t{n} * attr_floats(a, g.sh_coeffs) * 4);

  const gpu::ProjectParams pp = project_params(g, cam_);
  const uint32_t num_tiles = pp.cam.size.z * pp.cam.size.w;
  const uint32_t flags = (v.v_alpha ? S4D_RASTER_HAS_V_ALPHA : 0u) | (v.v_depth ? S4D_RASTER_HAS_V_DEPTH : 0u);
  const bool float_atomics = ctx_->info().float_atomic_add_buffer && !options_.force_cas_atomics;
  check_list_length(ctx_->info(), longest_last_, style_last_, !float_atomics, "differentiate");
  const engine::Buffer& colors = g[Attr::colors] ? *g[Attr::colors] : *g[Attr::sh];
  engine::Buffer& v_colors = colors_last_ ? *out[Attr::colors] : *out[Attr::sh];

  const engine::StageScope stage(*ctx_, "backward");
  rec.fill(grad2d_, 0, size_t{n} * S4D_G2D_STRIDE * 4 + 4);
  if (style_last_ && n > 0) rec.fill(*out[Attr::style_mlp], 0, size_t{n} * S4D_STYLE_MLP_STRIDE * 4);
  rec.barrier();
  std::vector<engine::Binding> bind = {
      S4D_BIND(RBWD_RANGES, ranges_),     S4D_BIND(RBWD_GAUSSIAN_IDS, gaussian_ids_),
      S4D_BIND(RBWD_XY, xy_),             S4D_BIND(RBWD_CONIC_OPACITY, conic_opacity_),
      S4D_BIND(RBWD_COLOR_DEPTH, color_depth_), S4D_BIND(RBWD_FINAL_T, final_t_),
      S4D_BIND(RBWD_LAST, last_),         S4D_BIND(RBWD_V_RGB, *v.v_rgb),
      S4D_BIND(RBWD_V_ALPHA, v.v_alpha ? *v.v_alpha : *v.v_rgb),
      S4D_BIND(RBWD_V_DEPTH, v.v_depth ? *v.v_depth : *v.v_rgb), S4D_BIND(RBWD_GRAD2D, grad2d_)};
  const StyleMlp* style = style_last_ ? g.style : nullptr;
  if (style != nullptr)
    bind.insert(bind.end(), {S4D_BIND(RBWD_QUADRIC, quadric_), S4D_BIND(RBWD_STYLE_MLP, *g[Attr::style_mlp]),
                             S4D_BIND(RBWD_V_STYLE_MLP, *out[Attr::style_mlp])});
  const uint32_t per_invocation = backward_pixels();
  using shaders::Id;
  const Id id = per_invocation == 1 ? (style != nullptr ? (float_atomics ? Id::style_raster_bwd_px1 : Id::style_raster_bwd_cas_px1)
                                                : (float_atomics ? Id::raster_bwd_px1 : Id::raster_bwd_cas_px1))
                            : (style != nullptr ? (float_atomics ? Id::style_raster_bwd : Id::style_raster_bwd_cas)
                                                : (float_atomics ? Id::raster_bwd : Id::raster_bwd_cas));
  const gpu::RasterParams raster = raster_params(style, pp.cam, background_, flags);
  // Specialised to the fewest lanes a subgroup of raster_bwd can have (its lane-parallel adds'
  // rounds, its reduce-scatter's halving steps), no more than the workgroup's invocations (a wider
  // subgroup is partial).
  const shaders::Entry& e = shaders::get(id);
  const uint32_t fewest = options_.min_subgroup_lanes != 0 ? options_.min_subgroup_lanes : ctx_->info().min_subgroup_size;
  const uint32_t min_lanes = std::clamp(fewest, 1u, uint32_t{S4D_TILE_PIXELS} / per_invocation);
  rec.dispatch_raw(ctx_->pipeline(e.name, e.spirv(), {{S4D_RBWD_SPEC_MIN_SUBGROUP, min_lanes}}), bind, &raster,
                   sizeof raster, num_tiles);
  rec.barrier();
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::project_bwd),
               {S4D_BIND(PBWD_MEANS, *g[Attr::means]), S4D_BIND(PBWD_LOG_SCALES, *g[Attr::log_scales]),
                S4D_BIND(PBWD_QUATS, *g[Attr::quats]), S4D_BIND(PBWD_OPACITY_LOGITS, *g[Attr::opacity_logits]),
                S4D_BIND(PBWD_SH, g[Attr::sh] ? *g[Attr::sh] : colors), S4D_BIND(PBWD_COLORS, colors), S4D_BIND(PBWD_INFO, info_),
                S4D_BIND(PBWD_CONIC_OPACITY, conic_opacity_), S4D_BIND(PBWD_GRAD2D, grad2d_),
                S4D_BIND(PBWD_V_MEANS, *out[Attr::means]), S4D_BIND(PBWD_V_LOG_SCALES, *out[Attr::log_scales]),
                S4D_BIND(PBWD_V_QUATS, *out[Attr::quats]), S4D_BIND(PBWD_V_OPACITY_LOGITS, *out[Attr::opacity_logits]),
                S4D_BIND(PBWD_V_SH, out[Attr::sh] ? *out[Attr::sh] : v_colors), S4D_BIND(PBWD_V_COLORS, v_colors)},
               pp, ceil_div(n, S4D_SPLAT_WG));
}

}  // namespace s4d::splat
