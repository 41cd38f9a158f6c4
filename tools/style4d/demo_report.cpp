#include "demo_report.h"

#include <iomanip>
#include <sstream>

#include "device_json.h"
#include "s4d/bench/frames_report.h"
#include "s4d/synth/dataset.h"
#include "s4d/util/atomic_file.h"

namespace s4d::cli {

namespace {

double mib(uint64_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

nlohmann::json timing_json(const bench::PrimitiveTiming& t) {
  return {{"n", t.n}, {"ms_gpu_p50", t.ms_p50}, {"keys_per_s", t.keys_per_s}, {"matches_twin", t.matches_twin}};
}

nlohmann::json demo_json(const DemoRecord& r) {
  nlohmann::json stages = nlohmann::json::array();
  for (const DemoStage& s : r.stages)
    stages.push_back({{"stage", s.name}, {"what", s.what}, {"seconds", s.seconds}, {"device_peak_mib", mib(s.device_peak_bytes)}});
  return {{"device", device_json(r.device)},
          {"engine_check", {{"radix_sort", timing_json(r.sort)}, {"exclusive_scan", timing_json(r.scan)}}},
          {"engine_ok", engine_ok(r)},
          {"stages", stages},
          {"host_peak_mib", mib(r.host_peak_bytes)},
          {"seconds", r.total_seconds},
          {"synth", r.synth},
          {"train", r.train},
          {"stylize", r.stylize},
          {"bench", r.bench},
          {"videos", r.videos},
          {"time_budget", r.time_budget},
          {"complete", true}};
}

std::string stage_table(const DemoRecord& r) {
  std::ostringstream md;
  md << "| stage | what | seconds | device memory peak (MiB) |\n|---|---|---|---|\n";
  for (const DemoStage& s : r.stages)
    md << "| " << s.name << " | " << s.what << " | " << fixed(s.seconds, 1) << " | " << fixed(mib(s.device_peak_bytes), 1) << " |\n";
  md << "| all | the whole demo | " << fixed(r.total_seconds, 1) << " | process peak resident memory: "
     << fixed(mib(r.host_peak_bytes), 0) << " MiB |\n";
  if (!r.time_budget.is_null())
    md << "\nTime budget " << fixed(r.time_budget.at("given_seconds").get<double>(), 0) << " s: training was given "
       << fixed(r.time_budget.at("train_seconds").get<double>(), 0) << " s, stylize "
       << fixed(r.time_budget.at("stylize_seconds").get<double>(), 0) << " s; the demo took "
       << fixed(r.total_seconds, 0) << " s.\n";
  return md.str();
}

std::string report_markdown(const DemoRecord& r) {
  std::ostringstream md;
  const nlohmann::json& sy = r.synth;
  const int frames = sy.at("frames").get<int>();
  const std::string first = s4d::synth::frame_file_name(0), last = s4d::synth::frame_file_name(frames - 1);
  const std::string cam0 = s4d::synth::camera_dir_name(0);
  md << "# Style4D demo report\n\n"
     << "Device: **" << r.device.name << "** (" << r.device.driver_info << "). The whole Style4D pipeline on the built-in "
     << "scene and style, nothing downloaded.\n\n## Stages\n\n"
     << stage_table(r);
  md << "\n## Built-in scene\n\n" << sy.at("cams").get<int>() << " cameras x " << frames << " frames at "
     << sy.at("width").get<int>() << "x" << sy.at("height").get<int>() << " in `data/` (DyNeRF layout). First and last frame of "
     << cam0 << ", the held-out test camera:\n\n"
     << "![first](data/" << cam0 << "/" << first << ") ![last](data/" << cam0 << "/" << last << ")\n";
  const nlohmann::json& t = r.train;
  md << "\n## Stages 1-2: static Gaussians, then 4DGS\n\n"
     << "Preset `" << t.at("preset").get<std::string>() << "` (" << t.at("iterations").get<int>() << " static + "
     << t.at("fine_iterations").get<int>() << " fine iterations), " << t.at("num_gaussians").get<int>() << " Gaussians. Held-out "
     << cam0 << " over all " << frames << " frames: PSNR **" << fixed(t.at("test_psnr").get<double>(), 2) << " dB**, SSIM "
     << fixed(t.at("test_ssim").get<double>(), 4) << " (the static stage alone: " << fixed(t.at("static_test_psnr").get<double>(), 2)
     << " dB). " << cam0 << ", first and last frame:\n\n"
     << "![first](run/eval/" << cam0 << "_" << first << ") ![last](run/eval/" << cam0 << "_" << last << ")\n";
  const nlohmann::json& st = r.stylize;
  const nlohmann::json& warp = st.at("warp_error");
  md << "\n## Stages 3-4: the built-in style\n\n"
     << "Every camera's frames restyled by the weight-free `patch` stylizer (" << fixed(st.at("stage3").at("seconds").get<double>(), 1)
     << " s), then the Style Gaussians trained against them (" << fixed(st.at("stage4").at("seconds").get<double>(), 1) << " s, "
     << st.at("settings").at("iterations").get<int>() << " iterations; " << cam0 << " against its stylized frames: PSNR "
     << fixed(st.at("stage4").at("test_psnr_vs_stylized").get<double>(), 2) << " dB). Temporal warp error of " << cam0
     << " over time (lower is steadier): the Style4D render **" << fixed(warp.at("test_camera").at("styled_render").get<double>(), 4)
     << "**, the 2D stylized frames " << fixed(warp.at("test_camera").at("stylized_frames_2d").get<double>(), 4)
     << ", the content " << fixed(warp.at("test_camera").at("content").get<double>(), 4)
     << ". On the spiral path (the camera orbits while time advances), under the renderer's exact flow: the Style4D render **"
     << fixed(warp.at("spiral_exact_flow").at("styled_render").get<double>(), 4)
     << "**, the same stylizer run on the original spiral render as a video "
     << fixed(warp.at("spiral_exact_flow").at("stylized_2d").get<double>(), 4) << ", the original render "
     << fixed(warp.at("spiral_exact_flow").at("original_render").get<double>(), 4)
     << " (under DIS flow, which the stylizer's warm start also follows: " << fixed(warp.at("spiral_styled_render").get<double>(), 4)
     << ", " << fixed(warp.at("spiral_stylized_2d").get<double>(), 4) << ", " << fixed(warp.at("spiral_original_render").get<double>(), 4)
     << "). Rows: content, stage-3 frames, Style4D renders of " << cam0 << " over time:\n\n"
     << "![contact sheet](run/style/builtin/contact_sheet.png)\n";
  md << "\n## Style4D-Bench\n\nThe test camera over all times and a spiral around the scene while time advances, for the "
     << "original scene and the style (full report with conventions, per-frame curves and CSV: [bench/report.md](bench/report.md); in a browser, with the "
     << "videos side by side and a sortable table: [bench/report.html](bench/report.html)).\n\n"
     << bench::report_table_markdown(r.bench) << "\n![bench frames](bench/contact_sheet.png)\n";
  md << "\n## Videos\n\n";
  for (const std::string& v : r.videos) md << "- [" << v << "](" << v << ")\n";
  md << "\n## Engine check (GPU vs CPU twin)\n\n| primitive | n | GPU ms (p50) | keys/s | matches twin |\n|---|---|---|---|---|\n";
  for (const auto* p : {&r.sort, &r.scan})
    md << "| " << p->primitive << " | " << p->n << " | " << fixed(p->ms_p50, 2) << " | " << fixed(p->keys_per_s, 0) << " | "
       << (p->matches_twin ? "yes" : "**NO**") << " |\n";
  return md.str();
}

}  // namespace

bool engine_ok(const DemoRecord& r) { return r.sort.matches_twin && r.scan.matches_twin; }

void write_demo_report(const DemoRecord& r) {
  util::write_file_atomic(r.out / "demo.json", demo_json(r).dump(2) + "\n");
  util::write_file_atomic(r.out / "report.md", report_markdown(r));
}

}  // namespace s4d::cli
