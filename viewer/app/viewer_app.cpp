#include "viewer_app.h"

#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "imgui_layer.h"
#include "input.h"
#include "panel.h"
#include "s4d/engine/check.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/scene/download_cloud.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/viewer/adaptive_resolution.h"
#include "s4d/viewer/camera_control.h"
#include "s4d/viewer/camera_path.h"
#include "s4d/viewer/dataset_cameras.h"
#include "s4d/viewer/frame_renderer.h"
#include "s4d/viewer/playback.h"
#include "style_switch.h"
#include "swapchain.h"
#include "window.h"

namespace s4d::viewer {

namespace fs = std::filesystem;

namespace {

constexpr double kOrbitRadiansPerPixel = 0.005;
constexpr double kFlySpeedPerDepth = 0.5;  // fly speed: half the pivot depth per second
constexpr float kBlendStep = 0.1f;         // the blend factor per [ or ] press

std::pair<int, int> window_size(const ViewerOptions& o, const io::CameraView& cam) {
  if (o.width > 0 && o.height > 0) return {o.width, o.height};
  const double w = std::clamp(static_cast<double>(cam.width), 640.0, 1280.0);
  return {static_cast<int>(w), static_cast<int>(w * cam.height / cam.width)};
}

// out_dir/<stem>_NNN.<ext> with the first free NNN.
fs::path next_free(const fs::path& dir, const char* stem, const char* ext) {
  for (int i = 0;; ++i) {
    char name[64];
    std::snprintf(name, sizeof(name), "%s_%03d.%s", stem, i, ext);
    if (!fs::exists(dir / name)) return dir / name;
  }
}

// Copies the packed pixels into the swapchain image: UNDEFINED -> TRANSFER_DST, then the copy.
// The panel's render pass takes it on from TRANSFER_DST_OPTIMAL.
void record_copy(engine::Recorder& rec, const engine::Buffer& pixels, VkImage image, VkExtent2D extent) {
  rec.barrier();  // present_pack's writes -> the copy's reads
  VkImageMemoryBarrier to_dst{.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .srcAccessMask = 0,
                              .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                              .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                              .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .image = image,
                              .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
  // The source stage is the one the submission waits for the acquire semaphore in.
  vkCmdPipelineBarrier(rec.handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &to_dst);
  VkBufferImageCopy region{.bufferOffset = 0,
                           .bufferRowLength = 0,
                           .bufferImageHeight = 0,
                           .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                           .imageOffset = {0, 0, 0},
                           .imageExtent = {extent.width, extent.height, 1}};
  vkCmdCopyBufferToImage(rec.handle(), pixels.handle(), image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
}

// What a frame shows: when all of it equals the last rendered frame's, that frame's pixels stand.
struct FrameView {
  splat::Camera camera;
  double time = 0;
  StyleSelection style;
  PixelOrder order = PixelOrder::rgba;
};

bool same_view(const FrameView& a, const FrameView& b) {
  const splat::Camera &p = a.camera, &q = b.camera;
  return p.world_to_cam == q.world_to_cam && p.fx == q.fx && p.fy == q.fy && p.cx == q.cx && p.cy == q.cy &&
         p.width == q.width && p.height == q.height && a.time == b.time && a.style.style == b.style.style &&
         a.style.mix == b.style.mix && a.style.alpha == b.style.alpha && a.order == b.order;
}

// One viewer session: the window and its device, the scene and the view, and what the frames so
// far measured. run_viewer drives it a frame at a time.
class Session {
 public:
  Session(const scene::TrainedRun& run, const ViewerOptions& options)
      : run_(run),
        options_(options),
        cameras_(dataset_cameras(run.dataset)),
        window_(open_window(run, options, cameras_)),
        ctx_(context_options(window_)),
        swapchain_(ctx_, window_.create_surface(ctx_.instance())),
        input_((resize_swapchain(), window_.handle())),  // the swapchain sized before the input and panel, as they expect
        imgui_(ctx_, window_.handle(), swapchain_),
        styles_(ctx_, run, options.style, options.storage),
        selection_(styles_.shown()),
        last_styled_(selection_.style > 0 ? selection_.style : 1),
        renderer_(ctx_, run.dataset.background),
        playback_{.time = options.time, .playing = options.play},
        control_(estimate_up(cameras_), kFlySpeedPerDepth * pivot_depth(options.camera)),
        recording_(!options.record.empty()),
        clip_(clip_seconds(run.dataset)),
        resolution_({.budget_ms = options.frame_budget_ms}) {
    control_.snap(cameras_[options.camera], pivot_depth(options.camera));
    for (const io::CameraView& c : cameras_) camera_names_.push_back(c.name);
    info_ = {.device = ctx_.info().name,
             .gaussians = styles_.source().size(),
             .dynamic = styles_.source().dynamic(),
             .cameras = &camera_names_,
             .styles = &run.styles};
    summary_.device = ctx_.info().name;
    // A warm-up render of the first view, unshown: the instance buffers grow to the scene here, so
    // the first frame on screen is not a partial one (overflow) followed by its re-render.
    const auto [w, h] = window_.framebuffer_size();
    if (w > 0 && h > 0)
      renderer_.render_now(styles_.source(), control_.camera(static_cast<uint32_t>(w), static_cast<uint32_t>(h)),
                           playback_.time, swapchain_.pixel_order());
    last_ = std::chrono::steady_clock::now();
  }

  // One pass of the frame loop; false once the window closes, Esc is pressed or exit_after is reached.
  bool frame() {
    if (window_.should_close()) return false;
    glfwPollEvents();
    const auto [w, h] = window_.framebuffer_size();
    if (w == 0 || h == 0) {  // minimised: render nothing, keep the clock from jumping
      glfwWaitEvents();
      last_ = std::chrono::steady_clock::now();
      return true;
    }
    if (recreate_ || swapchain_.extent().width != static_cast<uint32_t>(w) ||
        swapchain_.extent().height != static_cast<uint32_t>(h)) {
      swapchain_.recreate(static_cast<uint32_t>(w), static_cast<uint32_t>(h));
      imgui_.on_swapchain_recreated(swapchain_);
      recreate_ = false;
    }
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;

    const ImGuiIO& io = ImGui::GetIO();
    const InputFrame in = input_.poll(io.WantCaptureMouse, io.WantCaptureKeyboard);
    if (in.quit) return false;
    apply_input(in, seconds);
    const PanelActions act = draw_panel_frame();
    const int snap = act.snap_camera >= 0 ? act.snap_camera : in.snap_camera;
    if (snap >= 0 && static_cast<size_t>(snap) < cameras_.size()) snap_to(static_cast<size_t>(snap));

    wait_for_last_frame();
    const std::optional<uint32_t> image = swapchain_.acquire();
    if (!image) {
      imgui_.skip_frame();
      recreate_ = true;
      return true;
    }
    const bool screenshot = in.screenshot || act.screenshot;
    const FrameView view = present(*image, screenshot);
    info_.frame_ms = seconds * 1000;
    if (recording_) path_.add(control_, info_.width, info_.height, playback_.time);
    if (screenshot) save_screenshot(view);
    if (in.toggle_record || act.toggle_record) toggle_recording();
    ++summary_.frames;
    if (summary_.frames > 1) total_ms_ += info_.frame_ms;  // the first frame's time includes start-up
    return !(options_.exit_after && summary_.frames >= options_.exit_after);
  }

  // Waits for the device, writes a camera path still being recorded, and sums up the session.
  ViewerSummary finish() {
    ctx_.wait_idle();
    if (recording_ && !path_.empty())
      path_.write(options_.record.empty() ? next_free(options_.out_dir, "camera_path", "json") : options_.record);
    summary_.mean_frame_ms = summary_.frames > 1 ? total_ms_ / static_cast<double>(summary_.frames - 1) : 0;
    summary_.mean_scale = summary_.rasterized ? total_scale_ / static_cast<double>(summary_.rasterized) : 0;
    summary_.mean_rasterized_ms = measured_ ? total_raster_ms_ / static_cast<double>(measured_) : 0;
    return summary_;
  }

 private:
  static Window open_window(const scene::TrainedRun& run, const ViewerOptions& options,
                            const std::vector<io::CameraView>& cameras) {
    if (options.camera >= cameras.size())
      throw std::invalid_argument("--camera " + std::to_string(options.camera) + ": the run's dataset has cameras 0.." +
                                  std::to_string(cameras.size() - 1));
    const auto [win_w, win_h] = window_size(options, cameras[options.camera]);
    return Window("style4d view " + run.root.filename().string(), win_w, win_h);
  }
  static engine::ContextOptions context_options(Window& window) {
    engine::ContextOptions o = engine::ContextOptions::from_env();
    o.instance_extensions = window.instance_extensions();
    o.device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    o.can_present = &Window::can_present;
    return o;
  }
  void resize_swapchain() {
    const auto [fb_w, fb_h] = window_.framebuffer_size();
    swapchain_.recreate(static_cast<uint32_t>(fb_w), static_cast<uint32_t>(fb_h));
  }
  // The pivot: the median depth of the Gaussians, where they are at the current time.
  double pivot_depth(size_t i) {
    const splat::Camera cam = splat::to_splat_camera(cameras_[i]);
    return median_depth(cameras_[i], scene::download_cloud(ctx_, styles_.source().at(playback_.time, cam)).means, 1.0);
  }

  // Camera, playback, style and blend from this frame's input.
  void apply_input(const InputFrame& in, double seconds) {
    control_.orbit(-in.drag_dx * kOrbitRadiansPerPixel, -in.drag_dy * kOrbitRadiansPerPixel);
    control_.pan(in.pan_dx, in.pan_dy, swapchain_.extent().height);
    control_.zoom(in.scroll);
    control_.fly(in.fly_forward, in.fly_right, in.fly_up, seconds);
    if (in.toggle_play) playback_.playing = !playback_.playing;
    size_t& style = selection_.style;
    if (run_.styles.size() > 1 && in.next_style) style = (style + 1) % run_.styles.size();
    if (run_.styles.size() > 1 && in.toggle_original) style = style == 0 ? last_styled_ : 0;
    if (style > 0) last_styled_ = style;
    selection_.alpha = std::clamp(selection_.alpha + kBlendStep * static_cast<float>(in.blend_step), 0.0f, 1.0f);
    playback_.advance(seconds, clip_);
  }

  PanelActions draw_panel_frame() {
    imgui_.new_frame();
    info_.width = swapchain_.extent().width, info_.height = swapchain_.extent().height;
    info_.recording = recording_, info_.recorded = path_.size();
    const PanelActions act = draw_panel(info_, playback_, selection_);
    if (const std::string refused = styles_.update(selection_); !refused.empty()) info_.message = refused;
    return act;
  }

  void snap_to(size_t camera) {
    ctx_.wait_idle();  // the pivot reads the source's buffers, which the last frame may still read
    control_.snap(cameras_[camera], pivot_depth(camera));
    info_.message = "camera " + std::to_string(camera) + ": " + camera_names_[camera];
  }

  // Waits for the previous frame (its acquire semaphore and panel buffers are reused) and takes its
  // measurement: start of the render to its pixels on screen, the panel's work included.
  void wait_for_last_frame() {
    if (last_submit_) ctx_.wait(last_submit_);
    // The last frame rasterized past the instance buffers' capacity (they grew, and it showed the
    // nearest Gaussians only): present() renders it again.
    overflowed_ = rendered_ && !renderer_.finish();
    rendered_ = false;
    if (measuring_) {
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - measuring_->first).count();
      resolution_.measured(ms, measuring_->second);
      total_raster_ms_ += ms, ++measured_;
      measuring_.reset();
    }
  }

  // Renders the view when it changed, refines or completes it when due, copies the pixels into the
  // swapchain image under the panel and presents it. Moving: the policy's scale. Still for the
  // policy's settle time: refine to full resolution once, then reuse those pixels. A screenshot is
  // always of a full-resolution frame.
  FrameView present(uint32_t image, bool screenshot) {
    const auto t0 = std::chrono::steady_clock::now();
    engine::Recorder rec(ctx_, "viewer frame");
    const FrameView view{.camera = control_.camera(info_.width, info_.height),
                         .time = playback_.time,
                         .style = styles_.shown(),
                         .order = swapchain_.pixel_order()};
    const bool changed = !shown_ || !same_view(*shown_, view);
    if (changed) changed_at_ = t0;
    const double still_ms = std::chrono::duration<double, std::milli>(t0 - changed_at_).count();
    if (overflowed_ && !changed) {  // the same view at the same scale, complete this time
      renderer_.render(styles_.source(), view.camera, view.time, view.order, rec, renderer_.scale());
      rendered_ = true;
      ++summary_.rerendered;
    } else if (changed || (renderer_.scale() != 1 && (screenshot || resolution_.refine(still_ms)))) {
      const double scale = changed && !screenshot ? resolution_.scale(true) : 1.0;
      renderer_.render(styles_.source(), view.camera, view.time, view.order, rec, scale);
      rendered_ = true;
      shown_ = view;
      measuring_.emplace(t0, scale);
      const splat::Camera small = scaled_camera(view.camera, scale);
      info_.render_width = small.width, info_.render_height = small.height;
      ++summary_.rasterized;
      total_scale_ += scale;
    }
    record_copy(rec, renderer_.pixels(), swapchain_.image(image), swapchain_.extent());
    imgui_.record(rec.handle(), image, swapchain_.extent());
    last_submit_ = ctx_.submit(std::move(rec), {.wait = swapchain_.acquired(),
                                                .wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT,
                                                .signal = swapchain_.rendered(image)});
    if (!swapchain_.present(image)) recreate_ = true;
    info_.render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return view;
  }

  void save_screenshot(const FrameView& view) {
    ctx_.wait(last_submit_);
    if (rendered_ && !renderer_.finish()) {  // a complete frame to save (and to show from the next one)
      renderer_.render_now(styles_.source(), view.camera, view.time, view.order, renderer_.scale());
      ++summary_.rerendered;
    }
    rendered_ = false;
    fs::create_directories(options_.out_dir);
    const fs::path file = next_free(options_.out_dir, "screenshot", "png");
    io::write_png(file, renderer_.read_rgb());
    info_.message = "saved " + file.string();
  }

  void toggle_recording() {
    if (recording_ && !path_.empty()) {
      const fs::path file = options_.record.empty() ? next_free(options_.out_dir, "camera_path", "json") : options_.record;
      path_.write(file);
      info_.message = "saved " + file.string() + " (replay: style4d render --ply ... --cameras it)";
    }
    recording_ = !recording_;
  }

  const scene::TrainedRun& run_;
  const ViewerOptions& options_;
  const std::vector<io::CameraView> cameras_;
  std::vector<std::string> camera_names_;
  Window window_;
  engine::Context ctx_;
  Swapchain swapchain_;
  Input input_;
  ImGuiLayer imgui_;
  StyleSwitch styles_;
  StyleSelection selection_;
  size_t last_styled_;  // what T returns to from "original" (styles[0])
  FrameRenderer renderer_;
  Playback playback_;
  CameraControl control_;
  CameraPath path_;
  bool recording_;
  const double clip_;
  PanelInfo info_;
  ViewerSummary summary_;
  double total_ms_ = 0, total_scale_ = 0, total_raster_ms_ = 0;
  uint64_t measured_ = 0;  // rasterized frames whose time was measured (all but a last one)
  uint64_t last_submit_ = 0;
  bool rendered_ = false;    // the last submission rasterized a frame, which renderer.finish() checks
  bool overflowed_ = false;  // ... and it overflowed the instance buffers
  AdaptiveResolution resolution_;
  std::optional<FrameView> shown_;  // what renderer.pixels() hold
  std::chrono::steady_clock::time_point changed_at_;  // when the view last changed
  // The last rasterized frame, measured once its submission completes: start time and scale.
  std::optional<std::pair<std::chrono::steady_clock::time_point, double>> measuring_;
  bool recreate_ = false;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace

ViewerSummary run_viewer(const scene::TrainedRun& run, const ViewerOptions& options) {
  Session session(run, options);
  while (session.frame()) {
  }
  return session.finish();
}

}  // namespace s4d::viewer
