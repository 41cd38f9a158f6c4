#include "dataset_parts.h"
#include "s4d/data/camera_geometry.h"

#include <algorithm>
#include <set>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace s4d::data::detail {

void fail(const std::filesystem::path& path, const std::string& what) {
  throw std::runtime_error(path.string() + ": " + what);
}

std::pair<int, int> png_size(const std::filesystem::path& path) {
  // Signature (8 bytes), then the IHDR chunk: length (4), "IHDR", width and height (4 each, big endian).
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "cannot open");
  unsigned char b[24];
  f.read(reinterpret_cast<char*>(b), sizeof b);
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!f || !std::equal(kSignature, kSignature + 8, b) || !std::equal(b + 12, b + 16, "IHDR")) {
    fail(path, "not a PNG file");
  }
  auto be32 = [&](int at) {
    return static_cast<long>(b[at]) << 24 | static_cast<long>(b[at + 1]) << 16 | static_cast<long>(b[at + 2]) << 8 |
           static_cast<long>(b[at + 3]);
  };
  const long width = be32(16), height = be32(20);
  if (width <= 0 || height <= 0 || width > (1L << 24) || height > (1L << 24)) fail(path, "bad PNG size in IHDR");
  return {static_cast<int>(width), static_cast<int>(height)};
}

void downscale_camera(io::CameraView& camera, int factor) {
  camera.fx /= factor;
  camera.fy /= factor;
  camera.cx /= factor;
  camera.cy /= factor;
  camera.width = downscaled(camera.width, factor);
  camera.height = downscaled(camera.height, factor);
}

void add_rig_view(Dataset& dataset, const io::CameraView& camera, int camera_index, const std::string& camera_name,
                  const std::string& frame_name, const std::filesystem::path& image, int frame_in_file, size_t frame,
                  size_t frame_count) {
  View view;
  view.name = camera_name + "/" + frame_name;
  view.camera = camera;
  view.camera.name = view.name;
  view.image = image;
  view.frame_in_file = frame_in_file;
  view.camera.file_path = std::filesystem::relative(image, dataset.root).string();
  view.time = frame_count > 1 ? static_cast<double>(frame) / static_cast<double>(frame_count - 1) : 0.0;
  view.camera.time = view.time;
  view.camera_index = camera_index;
  view.test = camera_index == 0;
  dataset.views.push_back(std::move(view));
}

int checked_downscale(const std::filesystem::path& root, const LoadOptions& options) {
  if (options.downscale < 1) fail(root, "downscale must be >= 1, got " + std::to_string(options.downscale));
  return options.downscale;
}

namespace {

// 3DGS getNerfppNorm's radius: densification and learning rates scale with it.
double camera_extent(const Dataset& dataset) {
  std::vector<Vec3> centres;
  for (const View& v : dataset.views) {
    if (!v.test) centres.push_back(camera_centre(v.camera));
  }
  if (centres.empty()) fail(dataset.root, "no training views");
  Vec3 mean{};
  for (const auto& c : centres) {
    for (size_t k = 0; k < 3; ++k) mean[k] += c[k] / static_cast<double>(centres.size());
  }
  double max_distance = 0;
  for (const auto& c : centres) {
    max_distance = std::max(max_distance, std::hypot(c[0] - mean[0], c[1] - mean[1], c[2] - mean[2]));
  }
  return 1.1 * max_distance;
}

}  // namespace

void select_frames(Dataset& dataset, std::pair<int, int> range) {
  std::vector<double> times;
  for (const View& v : dataset.views) times.push_back(v.time);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  const int count = static_cast<int>(times.size());
  if (range.second > count) {
    fail(dataset.root, "--frames " + std::to_string(range.first) + ":" + std::to_string(range.second) + ": the dataset has " +
                           std::to_string(count) + " frames (distinct times)");
  }
  const double t0 = times[static_cast<size_t>(range.first)], t1 = times[static_cast<size_t>(range.second - 1)];
  std::vector<View> kept;
  for (View& v : dataset.views) {
    if (v.time < t0 || v.time > t1) continue;
    v.time = t1 > t0 ? (v.time - t0) / (t1 - t0) : 0.0;
    v.camera.time = v.time;
    kept.push_back(std::move(v));
  }
  dataset.views = std::move(kept);
}

void finish_dataset(Dataset& dataset, const LoadOptions& options, const std::array<float, 3>& default_background,
                    const std::vector<std::filesystem::path>& point_files) {
  if (options.frames) select_frames(dataset, *options.frames);
  dataset.downscale = options.downscale;
  dataset.extent = camera_extent(dataset);
  choose_background(dataset, options, default_background);
  for (const std::filesystem::path& name : point_files) {
    const std::filesystem::path file = dataset.root / name;
    if (!std::filesystem::exists(file)) continue;
    read_points(file, dataset.points, dataset.colors);
    dataset.points_file = file;
    break;
  }
}

std::string frame_count_mismatch(const std::vector<std::filesystem::path>& frames,
                                 const std::string& reference_name, const std::vector<std::filesystem::path>& reference) {
  constexpr size_t kNamed = 5;  // a damaged capture may lack hundreds; the first few say where
  std::set<std::string> have, ref;
  for (const auto& f : frames) have.insert(f.filename().string());
  for (const auto& f : reference) ref.insert(f.filename().string());
  std::string missing, extra;
  size_t n_missing = 0, n_extra = 0;
  for (size_t k = 0; k < reference.size(); ++k) {
    const std::string file = reference[k].filename().string();
    if (have.count(file)) continue;
    if (n_missing++ < kNamed)
      missing += (missing.empty() ? "" : ", ") + file + " (frame " + std::to_string(k) + " of " + reference_name + ")";
  }
  for (const auto& f : frames)
    if (!ref.count(f.filename().string()) && n_extra++ < kNamed) extra += (extra.empty() ? "" : ", ") + f.filename().string();
  std::string out = "has " + std::to_string(frames.size()) + " frames but " + reference_name + " has " +
                    std::to_string(reference.size());
  if (n_missing > 0) out += ": missing " + missing + (n_missing > kNamed ? " and " + std::to_string(n_missing - kNamed) + " more" : "");
  if (n_extra > 0)
    out += (n_missing > 0 ? "; " : ": ") + std::string("not in ") + reference_name + ": " + extra +
           (n_extra > kNamed ? " and " + std::to_string(n_extra - kNamed) + " more" : "");
  return out + "; every camera needs the same frame count";
}

}  // namespace s4d::data::detail

namespace s4d::data {

std::pair<int, int> parse_frame_range(const std::string& text, const std::string& option) {
  auto number = [&](const std::string& s) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
      throw std::invalid_argument(option + ": expected N or A:B (frame indices), got '" + text + "'");
    return std::stoi(s);
  };
  const size_t colon = text.find(':');
  const std::pair<int, int> range =
      colon == std::string::npos ? std::pair{0, number(text)} : std::pair{number(text.substr(0, colon)), number(text.substr(colon + 1))};
  if (range.second <= range.first)
    throw std::invalid_argument(option + ": '" + text + "' selects no frame (A:B needs A < B, N needs N >= 1)");
  return range;
}

}  // namespace s4d::data
