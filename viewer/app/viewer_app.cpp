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

}  // namespace

ViewerSummary run_viewer(const scene::TrainedRun& run, const ViewerOptions& options) {
  const std::vector<io::CameraView> cameras = dataset_cameras(run.dataset);
  if (options.camera >= cameras.size())
    throw std::invalid_argument("--camera " + std::to_string(options.camera) + ": the run's dataset has cameras 0.." +
                                std::to_string(cameras.size() - 1));
  const auto [win_w, win_h] = window_size(options, cameras[options.camera]);
  Window window("style4d view " + run.root.filename().string(), win_w, win_h);

  engine::ContextOptions context_options = engine::ContextOptions::from_env();
  context_options.instance_extensions = window.instance_extensions();
  context_options.device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  context_options.can_present = &Window::can_present;
  engine::Context ctx(context_options);

  Swapchain swapchain(ctx, window.create_surface(ctx.instance()));
  const auto [fb_w, fb_h] = window.framebuffer_size();
  swapchain.recreate(static_cast<uint32_t>(fb_w), static_cast<uint32_t>(fb_h));
  Input input(window.handle());
  ImGuiLayer imgui(ctx, window.handle(), swapchain);

  StyleSwitch styles(ctx, run, options.style);
  StyleSelection selection = styles.shown();
  size_t last_styled = selection.style > 0 ? selection.style : 1;  // what T returns to from "original" (styles[0])
  FrameRenderer renderer(ctx, run.dataset.background);
  std::vector<std::string> camera_names;
  for (const io::CameraView& c : cameras) camera_names.push_back(c.name);
  Playback playback{.time = options.time, .playing = options.play};

  // The pivot: the median depth of the Gaussians, where they are at the current time.
  auto pivot_depth = [&](size_t i) {
    const splat::Camera cam = splat::to_splat_camera(cameras[i]);
    return median_depth(cameras[i], scene::download_cloud(ctx, styles.source().at(playback.time, cam)).means, 1.0);
  };
  CameraControl control(estimate_up(cameras), kFlySpeedPerDepth * pivot_depth(options.camera));
  control.snap(cameras[options.camera], pivot_depth(options.camera));
  CameraPath path;
  bool recording = !options.record.empty();
  const fs::path out_dir = options.out_dir;
  const double clip = clip_seconds(run.dataset);

  PanelInfo info{.device = ctx.info().name,
                 .gaussians = styles.source().size(),
                 .dynamic = styles.source().dynamic(),
                 .cameras = &camera_names,
                 .styles = &run.styles};
  ViewerSummary summary{.device = ctx.info().name};
  double total_ms = 0, total_scale = 0, total_raster_ms = 0;
  uint64_t measured = 0;  // rasterized frames whose time was measured (all but a last one)
  uint64_t last_submit = 0;
  bool rendered = false;  // the last submission rasterized a frame, which renderer.finish() checks
  AdaptiveResolution resolution({.budget_ms = options.frame_budget_ms});
  std::optional<FrameView> shown;  // what renderer.pixels() hold
  std::chrono::steady_clock::time_point changed_at;  // when the view last changed
  // The last rasterized frame, measured once its submission completes: start time and scale.
  std::optional<std::pair<std::chrono::steady_clock::time_point, double>> measuring;
  bool recreate = false;
  {  // A warm-up render of the first view, unshown: the instance buffers grow to the scene here, so
     // the first frame on screen is not a partial one (overflow) followed by its re-render.
    const auto [w, h] = window.framebuffer_size();
    if (w > 0 && h > 0)
      renderer.render_now(styles.source(), control.camera(static_cast<uint32_t>(w), static_cast<uint32_t>(h)),
                          playback.time, swapchain.pixel_order());
  }
  auto last = std::chrono::steady_clock::now();

  while (!window.should_close()) {
    glfwPollEvents();
    const auto [w, h] = window.framebuffer_size();
    if (w == 0 || h == 0) {  // minimised: render nothing, keep the clock from jumping
      glfwWaitEvents();
      last = std::chrono::steady_clock::now();
      continue;
    }
    if (recreate || swapchain.extent().width != static_cast<uint32_t>(w) ||
        swapchain.extent().height != static_cast<uint32_t>(h)) {
      swapchain.recreate(static_cast<uint32_t>(w), static_cast<uint32_t>(h));
      imgui.on_swapchain_recreated(swapchain);
      recreate = false;
    }
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last).count();
    last = now;

    // Input and panel.
    const ImGuiIO& io = ImGui::GetIO();
    const InputFrame in = input.poll(io.WantCaptureMouse, io.WantCaptureKeyboard);
    if (in.quit) break;
    control.orbit(-in.drag_dx * kOrbitRadiansPerPixel, -in.drag_dy * kOrbitRadiansPerPixel);
    control.pan(in.pan_dx, in.pan_dy, swapchain.extent().height);
    control.zoom(in.scroll);
    control.fly(in.fly_forward, in.fly_right, in.fly_up, seconds);
    if (in.toggle_play) playback.playing = !playback.playing;
    size_t& style = selection.style;
    if (run.styles.size() > 1 && in.next_style) style = (style + 1) % run.styles.size();
    if (run.styles.size() > 1 && in.toggle_original) style = style == 0 ? last_styled : 0;
    if (style > 0) last_styled = style;
    selection.alpha = std::clamp(selection.alpha + kBlendStep * static_cast<float>(in.blend_step), 0.0f, 1.0f);
    playback.advance(seconds, clip);
    imgui.new_frame();
    info.width = swapchain.extent().width, info.height = swapchain.extent().height;
    info.recording = recording, info.recorded = path.size();
    const PanelActions act = draw_panel(info, playback, selection);
    if (const std::string refused = styles.update(selection); !refused.empty()) info.message = refused;
    const int snap = act.snap_camera >= 0 ? act.snap_camera : in.snap_camera;
    if (snap >= 0 && static_cast<size_t>(snap) < cameras.size()) {
      ctx.wait_idle();  // the pivot reads the source's buffers, which the last frame may still read
      control.snap(cameras[static_cast<size_t>(snap)], pivot_depth(static_cast<size_t>(snap)));
      info.message = "camera " + std::to_string(snap) + ": " + camera_names[static_cast<size_t>(snap)];
    }

    // The frame: wait for the previous one (its acquire semaphore and panel buffers are reused).
    if (last_submit) ctx.wait(last_submit);
    // The last frame rasterized past the instance buffers' capacity (they grew, and it showed the
    // nearest Gaussians only): render it again, below.
    const bool overflowed = rendered && !renderer.finish();
    rendered = false;
    if (measuring) {  // start of the render to its pixels on screen, the panel's work included
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - measuring->first).count();
      resolution.measured(ms, measuring->second);
      total_raster_ms += ms, ++measured;
      measuring.reset();
    }
    const std::optional<uint32_t> image = swapchain.acquire();
    if (!image) {
      imgui.skip_frame();
      recreate = true;
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    engine::Recorder rec(ctx, "viewer frame");
    // Moving: the policy's scale. Still for the policy's settle time: refine to full resolution
    // once, then reuse those pixels. A screenshot is always of a full-resolution frame.
    const bool screenshot = in.screenshot || act.screenshot;
    const FrameView view{.camera = control.camera(info.width, info.height),
                         .time = playback.time,
                         .style = styles.shown(),
                         .order = swapchain.pixel_order()};
    const bool changed = !shown || !same_view(*shown, view);
    if (changed) changed_at = t0;
    const double still_ms = std::chrono::duration<double, std::milli>(t0 - changed_at).count();
    if (overflowed && !changed) {  // the same view at the same scale, complete this time
      renderer.render(styles.source(), view.camera, view.time, view.order, rec, renderer.scale());
      rendered = true;
      ++summary.rerendered;
    } else if (changed || (renderer.scale() != 1 && (screenshot || resolution.refine(still_ms)))) {
      const double scale = changed && !screenshot ? resolution.scale(true) : 1.0;
      renderer.render(styles.source(), view.camera, view.time, view.order, rec, scale);
      rendered = true;
      shown = view;
      measuring.emplace(t0, scale);
      const splat::Camera small = scaled_camera(view.camera, scale);
      info.render_width = small.width, info.render_height = small.height;
      ++summary.rasterized;
      total_scale += scale;
    }
    record_copy(rec, renderer.pixels(), swapchain.image(*image), swapchain.extent());
    imgui.record(rec.handle(), *image, swapchain.extent());
    last_submit = ctx.submit(std::move(rec), {.wait = swapchain.acquired(),
                                              .wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT,
                                              .signal = swapchain.rendered(*image)});
    if (!swapchain.present(*image)) recreate = true;
    info.render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    info.frame_ms = seconds * 1000;

    if (recording) path.add(control, info.width, info.height, playback.time);
    if (screenshot) {
      ctx.wait(last_submit);
      if (rendered && !renderer.finish()) {  // a complete frame to save (and to show from the next one)
        renderer.render_now(styles.source(), view.camera, view.time, view.order, renderer.scale());
        ++summary.rerendered;
      }
      rendered = false;
      fs::create_directories(out_dir);
      const fs::path file = next_free(out_dir, "screenshot", "png");
      io::write_png(file, renderer.read_rgb());
      info.message = "saved " + file.string();
    }
    if (in.toggle_record || act.toggle_record) {
      if (recording && !path.empty()) {
        const fs::path file = options.record.empty() ? next_free(out_dir, "camera_path", "json") : options.record;
        path.write(file);
        info.message = "saved " + file.string() + " (replay: style4d render --ply ... --cameras it)";
      }
      recording = !recording;
    }
    ++summary.frames;
    if (summary.frames > 1) total_ms += info.frame_ms;  // the first frame's time includes start-up
    if (options.exit_after && summary.frames >= options.exit_after) break;
  }
  ctx.wait_idle();
  if (recording && !path.empty())
    path.write(options.record.empty() ? next_free(out_dir, "camera_path", "json") : options.record);
  summary.mean_frame_ms = summary.frames > 1 ? total_ms / static_cast<double>(summary.frames - 1) : 0;
  summary.mean_scale = summary.rasterized ? total_scale / static_cast<double>(summary.rasterized) : 0;
  summary.mean_rasterized_ms = measured ? total_raster_ms / static_cast<double>(measured) : 0;
  return summary;
}

}  // namespace s4d::viewer
