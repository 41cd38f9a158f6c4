// The tile-sorted Gaussian rasterizer on the GPU (ALGORITHMS.md 1): forward render to RGB, alpha,
// expected depth and per-pixel contributor counts, and the backward pass to every Gaussian
// parameter. Its CPU twin is training/ref/include/s4d/ref/splat_raster_ref.h. With per-Gaussian
// style MLPs (GaussianParams::style) it runs the fused style kernels instead, whose twin is
// training/ref/include/s4d/ref/style_raster_ref.h.
//
// A forward is one command buffer with no host read in the middle: the number of tile instances
// stays on the device (instance_args.comp writes the live count and the indirect dispatches of the
// tile sort and tile_ranges), the instance buffers keep a capacity between frames, and after the
// frame finish_forward() reads the count: past the capacity, emit_instances dropped the rest, so
// the buffers grow and the frame must be recorded again (rare: the capacity grows by a quarter
// past the largest count seen). record_forward() records into the caller's command buffer, so a
// viewer frame or training step can put more work in the same submission; forward() records,
// submits, waits and finishes. Every intermediate buffer is owned here and grows on demand.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/splat/gaussian_buffers.h"
#include "s4d/primitives/radix_sort.h"

namespace s4d::splat {

// A pinhole camera in this project's convention: OpenCV axes (x right, y down, z forward), pixel
// (i, j) centred at (i + 0.5, j + 0.5), u = fx x/z + cx.
struct Camera {
  std::array<float, 12> world_to_cam{};  // rows of [R | t], row-major 3x4
  float fx = 0, fy = 0, cx = 0, cy = 0;
  uint32_t width = 0, height = 0;
};

// The depth input of the style MLPs, from t*, the depth of maximum response along the pixel ray
// (GOF; ALGORITHMS.md 4.4).
enum class StyleDepth : uint32_t {
  ndc = 0,       // far/(far - near) (1 - near/t*), near 0.2, far 100, t* clamped to [near, far]: in [0, 1]
  relative = 1,  // (t* - z_i) * depth_scale, z_i the Gaussian's camera-space centre depth
};

// Per-Gaussian style MLPs ("Style Gaussians", ALGORITHMS.md 4.3; layout in
// shaders/shared/s4d_style_splat.h). With GaussianParams::style set, every (pixel, Gaussian) pair
// evaluates Gaussian i's MLP (GaussianParams[Attr::style_mlp]) on x = (time, depth feature) inside
// the blend loop and blends colour c_i + dRGB with alpha min(0.99, (o_i + dO) G). Zero W3 and b3
// render exactly as without.
struct StyleMlp {
  float time = 0;                           // x0, the normalised time in [0, 1)
  StyleDepth depth = StyleDepth::ndc;
  // StyleDepth::relative only. The default 1 keeps world units; a caller that wants the feature in
  // [-1, 1] over a Gaussian's 3-sigma extent sets 1 / (3 * its typical scale).
  float depth_scale = 1;
  bool input_sigmoid = false;  // x = sigmoid(x) before the first layer (SuperGaussians does)
};

// Device-resident Gaussian parameters, one buffer per attribute (gaussian_buffers.h): means,
// log_scales, quats (w, x, y, z; normalised in the kernel) and opacity_logits always; sh unless
// colors is set (colors replaces the SH colour); style_mlp [N*52] when `style` is set. sh and
// style_mlp may be stored as packed halves (Storage::f16, a trained model's render-side storage):
// the forward then runs the _half kernel variants, and backward() refuses them.
struct GaussianParams {
  GaussianBuffers<const engine::Buffer> buffers;
  uint32_t count = 0;
  uint32_t sh_degree = 0;  // active degree 0..3
  uint32_t sh_coeffs = 1;  // K stored per Gaussian and channel, >= (sh_degree + 1)^2
  const StyleMlp* style = nullptr;  // nullptr: the plain rasterizer
  Storage sh_storage = Storage::f32;
  Storage style_mlp_storage = Storage::f32;

  // How attribute a is stored (only sh and style_mlp may be halves), and its buffer's bytes in use.
  Storage storage(Attr a) const {
    return a == Attr::sh ? sh_storage : a == Attr::style_mlp ? style_mlp_storage : Storage::f32;
  }
  size_t bytes(Attr a) const { return attr_bytes(a, sh_coeffs, count, storage(a)); }

  const engine::Buffer*& operator[](Attr a) { return buffers[a]; }
  const engine::Buffer* operator[](Attr a) const { return buffers[a]; }
};

// Cotangents of the forward images. v_rgb is required; v_alpha and v_depth are optional.
struct ImageCotangents {
  const engine::Buffer* v_rgb = nullptr;    // [H*W*3]
  const engine::Buffer* v_alpha = nullptr;  // [H*W]
  const engine::Buffer* v_depth = nullptr;  // [H*W]
};

struct RasterizerOptions {
  bool force_cas_atomics = false;  // use the compare-and-swap gradient path even with float atomics
  // Tile instances the buffers hold before the first frame (exactly; growth adds headroom). Tests
  // set it tiny to force the overflow path.
  uint32_t initial_instance_capacity = 1024;
  // Pixels per invocation of the backward kernel (s4d_splat.h): 0 picks by device type,
  // S4D_RBWD_PIXELS_CPU on a CPU device and S4D_RBWD_PIXELS_GPU elsewhere; tests and benches set
  // 1 or 8 to run either variant anywhere.
  uint32_t backward_pixels = 0;
  // Pixels per invocation of the forward kernel, likewise (S4D_RFWD_PIXELS_CPU or _GPU).
  uint32_t forward_pixels = 0;
  // The fewest lanes the backward may assume a subgroup has (S4D_RBWD_SPEC_MIN_SUBGROUP): 0 takes
  // the device's; a smaller power of two is always correct, and lets tests run on lavapipe the
  // path a device whose subgroups vary in size takes.
  uint32_t min_subgroup_lanes = 0;
};

struct RenderStats {
  uint32_t instances = 0;         // (tile, Gaussian) pairs blended
  uint32_t longest_tile_list = 0; // entries of the fullest tile
};

class Rasterizer {
 public:
  explicit Rasterizer(engine::Context& ctx, std::string name = "rasterizer", RasterizerOptions options = {});

  // Renders and waits: record_forward, one submission (two after an overflow), finish_forward.
  // Throws std::invalid_argument on inconsistent parameters or a camera the kernels cannot address,
  // std::runtime_error when a tile list is longer than the device can blend.
  RenderStats forward(const GaussianParams& g, const Camera& cam, const std::array<float, 3>& background);

  // Records a forward into `rec`. The outputs are valid once `rec` has run and finish_forward()
  // returned stats; `g`'s buffers must hold their values when `rec` runs (a scene source may
  // compute them earlier in the same command buffer, followed by a barrier).
  void record_forward(engine::Recorder& rec, const GaussianParams& g, const Camera& cam,
                      const std::array<float, 3>& background);
  // After the recorded forward's submission completed (Context::wait): its stats, read from
  // host-visible memory the frame wrote (no device work), or nullopt when the tile instances
  // overflowed the buffers (grown now: record the frame again). Throws as forward() does.
  std::optional<RenderStats> finish_forward();
  // Frames recorded again because the instance buffers overflowed, and their capacity.
  uint32_t overflows() const { return overflows_; }
  uint32_t instance_capacity() const { return instance_capacity_; }

  // Backward of the last forward(), which must have used the same `g`. Waits. Gradients are assigned
  // (not accumulated): means, log_scales, quats and opacity_logits always; sh unless colours were
  // used, colors when they were, style_mlp when the forward used style MLPs.
  void backward(const GaussianParams& g, const ImageCotangents& v, const GaussianGrads& out);
  // The same recorded into `rec` (after a barrier() behind whatever wrote the cotangents); the
  // gradients hold once `rec` has run.
  void record_backward(engine::Recorder& rec, const GaussianParams& g, const ImageCotangents& v,
                       const GaussianGrads& out);

  // Outputs of the last forward, row-major [H, W(, 3)].
  const engine::Buffer& rgb() const { return rgb_; }              // float [H*W*3]
  const engine::Buffer& alpha() const { return alpha_; }          // float [H*W], 1 - T_final
  const engine::Buffer& depth() const { return depth_; }          // float [H*W], sum depth_i alpha_i T_i
  const engine::Buffer& contributors() const { return count_; }   // u32 [H*W]
  // u32 [H*W]: 1 + position in the pixel's tile list of its last blended Gaussian (0: none).
  const engine::Buffer& last_contributor() const { return last_; }
  // Per-Gaussian intermediates of the last forward (layouts in s4d_splat.h).
  const engine::Buffer& xy() const { return xy_; }
  const engine::Buffer& conic_opacity() const { return conic_opacity_; }
  const engine::Buffer& color_depth() const { return color_depth_; }
  const engine::Buffer& info() const { return info_; }
  // Style forwards only: GOF quadrics, [N * S4D_STYLE_QUADRIC_STRIDE] (s4d_style_splat.h).
  const engine::Buffer& quadric() const { return quadric_; }
  // The last forward's blend lists: per tile a (begin, end) range into the instance ids.
  const engine::Buffer& tile_ranges() const { return ranges_; }    // uvec2 [tiles]
  const engine::Buffer& instance_ids() const { return gaussian_ids_; }  // u32 [instances]
  // Screen-space cotangents of the last backward, [N * S4D_G2D_STRIDE] (densification reads the mean's).
  const engine::Buffer& grad2d() const { return grad2d_; }
  const Camera& camera() const { return cam_; }
  engine::Context& context() const { return *ctx_; }
  // Bytes of device memory in this rasterizer's buffers. They only grow, so this is its peak so far.
  size_t device_bytes() const;
  // Pixels per invocation of the backward kernel on this device (RasterizerOptions::backward_pixels).
  uint32_t backward_pixels() const;
  // Pixels per invocation of the forward kernel on this device (RasterizerOptions::forward_pixels).
  uint32_t forward_pixels() const;

 private:
  engine::Buffer buffer(const char* what, size_t bytes) const;  // named after this rasterizer
  uint32_t pixels_by_device(uint32_t forced, uint32_t cpu, uint32_t gpu) const;
  void reserve_gaussians(uint32_t n);
  void reserve_instances(uint32_t n);        // grows to at least n, with headroom
  void allocate_instances(uint32_t capacity);  // exactly `capacity`
  void reserve_pixels(uint32_t width, uint32_t height);
  void reserve_quadrics(uint32_t n);

  engine::Context* ctx_;
  std::string name_;
  RasterizerOptions options_;
  uint32_t gaussian_capacity_ = 0, instance_capacity_ = 0, pixel_capacity_ = 0, tile_capacity_ = 0;

  // State of the last forward, reused by backward.
  Camera cam_{};
  std::array<float, 3> background_{};
  uint32_t count_last_ = 0;
  uint32_t longest_last_ = 0;
  bool colors_last_ = false;
  uint32_t sh_degree_last_ = 0, sh_coeffs_last_ = 0;
  bool style_last_ = false;
  StyleMlp style_settings_last_{};  // the last forward's style settings
  bool have_forward_ = false;
  bool pending_ = false;  // a forward was recorded and not yet finished
  uint32_t overflows_ = 0;

  engine::Buffer xy_, conic_opacity_, color_depth_, info_, depth_keys_, tiles_touched_, sorted_ids_, offsets_;
  engine::Buffer tile_keys_, gaussian_ids_, ranges_;
  engine::Buffer rgb_, alpha_, depth_, count_, last_, final_t_;
  engine::Buffer grad2d_, scan_scratch_, list_stats_, totals_;
  engine::Buffer args_;  // gpu::InstanceArgs of the last recorded forward
  // Copied at the end of each forward for finish_forward: count_tiles' totals (instances mod 2^32,
  // carries, largest rectangle) and the longest tile list.
  struct Readback {
    uint32_t totals[3];
    uint32_t longest;
  };
  engine::Buffer readback_;  // staging, one Readback
  engine::Buffer quadric_;  // style MLP inputs, [N*S4D_STYLE_QUADRIC_STRIDE]; allocated on first use
  uint32_t quadric_capacity_ = 0;
  primitives::RadixSortScratch depth_sort_, tile_sort_;
};

}  // namespace s4d::splat
