#include "s4d/style_gaussians/stylized_frames.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <map>

#include "s4d/data/frame_cache.h"
#include "s4d/frame_stylizers/warp_error.h"
#include "s4d/util/atomic_file.h"
#include "s4d/util/progress.h"

namespace s4d::style_gaussians {

namespace fs = std::filesystem;

namespace {

constexpr size_t kFrameCacheBytes = size_t{256} << 20;

// The views of each sequence in time order: one per DyNeRF camera, one per D-NeRF split.
std::map<std::string, std::vector<const data::View*>> sequences_of(const data::Dataset& d) {
  std::map<std::string, std::vector<const data::View*>> out;
  for (const data::View& v : d.views) {
    const std::string key = v.camera_index >= 0 ? "cam" + std::to_string(v.camera_index) : (v.test ? "test" : "train");
    out[key].push_back(&v);
  }
  for (auto& [name, views] : out)
    std::stable_sort(views.begin(), views.end(), [](const data::View* a, const data::View* b) { return a->time < b->time; });
  return out;
}

fs::path frame_path(const fs::path& dir, const data::View& v) { return dir / (v.name + ".png"); }

nlohmann::json manifest_of(const nlohmann::json& key, const data::Dataset& d) {
  nlohmann::json names = nlohmann::json::array();
  for (const data::View& v : d.views) names.push_back(v.name);
  return {{"key", key}, {"downscale", d.downscale}, {"background", d.background}, {"frames", names}};
}

bool cache_valid(const fs::path& dir, const nlohmann::json& manifest, const data::Dataset& d) {
  std::ifstream in(dir / "manifest.json");
  if (!in) return false;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return false;
  }
  if (j.value("inputs", nlohmann::json()) != manifest) return false;
  return std::all_of(d.views.begin(), d.views.end(), [&](const data::View& v) { return fs::exists(frame_path(dir, v)); });
}

}  // namespace

nlohmann::json StylizedFrames::to_json() const {
  nlohmann::json seq = nlohmann::json::array();
  for (const Sequence& s : sequences)
    seq.push_back({{"name", s.name}, {"content_warp_error", s.content_warp_error}, {"stylized_warp_error", s.stylized_warp_error}});
  return {{"reused", reused}, {"seconds", seconds}, {"frames", dataset.views.size()}, {"sequences", seq}};
}

StylizedFrames stylize_dataset(const data::Dataset& content, const frame_stylizers::Stylizer& stylizer, const io::ImageF& style,
                               const frame_stylizers::StylizeSettings& settings, const nlohmann::json& key, const fs::path& out_dir) {
  const nlohmann::json manifest = manifest_of(key, content);
  StylizedFrames out;
  out.dataset = content;
  out.dataset.downscale = 1;  // the PNGs are at the training resolution already
  for (data::View& v : out.dataset.views) v.image = frame_path(out_dir, v), v.frame_in_file = -1;
  out.reused = cache_valid(out_dir, manifest, content);

  data::FrameCache frames(content, kFrameCacheBytes);
  const auto start = std::chrono::steady_clock::now();
  util::Progress progress("stage 3 stylize", content.views.size());
  size_t done = 0;
  std::vector<StylizedFrames::Sequence> sequences;
  for (const auto& [name, views] : sequences_of(content)) {
    std::vector<io::ImageF> input;
    for (const data::View* v : views) input.push_back(frames.get(*v));
    std::vector<io::ImageF> result;
    if (out.reused) {
      for (const data::View* v : views) result.push_back(io::read_png(frame_path(out_dir, *v)));
    } else {
      result = stylizer.stylize(input, style, settings, [&](int k, int) { progress.update(done + static_cast<size_t>(k)); });
      for (size_t k = 0; k < views.size(); ++k) {
        const fs::path file = frame_path(out_dir, *views[k]);
        fs::create_directories(file.parent_path());
        io::write_png(file, result[k]);
      }
    }
    done += views.size();
    StylizedFrames::Sequence s{name, 0, 0};
    if (views.size() >= 2) s.content_warp_error = frame_stylizers::warp_error(input, input), s.stylized_warp_error = frame_stylizers::warp_error(input, result);
    sequences.push_back(s);
  }
  out.sequences = std::move(sequences);
  if (!out.reused) {
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.finish();
    util::write_file_atomic(out_dir / "manifest.json", nlohmann::json{{"inputs", manifest}, {"stylized", out.to_json()}}.dump(2) + "\n");
  }
  return out;
}

}  // namespace s4d::style_gaussians
