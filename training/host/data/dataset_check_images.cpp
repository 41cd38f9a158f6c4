// check_images: every view's image or video frame exists and has its camera's size.
#include <algorithm>
#include <cctype>
#include <exception>
#include <fstream>
#include <map>
#include <optional>
#include <utility>

#include "dataset_check_parts.h"
#include "dataset_parts.h"
#include "s4d/data/video_reader.h"

namespace s4d::data::detail {
namespace {

// (width, height) from a baseline or progressive JPEG's SOFn segment, without decoding the image.
std::pair<int, int> jpeg_size(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) detail::fail(path, "cannot open");
  auto byte = [&]() {
    const int c = f.get();
    if (c == std::char_traits<char>::eof()) detail::fail(path, "not a JPEG file (no frame header before the end)");
    return c;
  };
  if (byte() != 0xFF || byte() != 0xD8) detail::fail(path, "not a JPEG file");
  for (;;) {
    int marker = byte();
    if (marker != 0xFF) detail::fail(path, "not a JPEG file (bad marker)");
    while (marker == 0xFF) marker = byte();  // fill bytes
    if (marker == 0xD8 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;  // no length
    const int length = byte() << 8 | byte();
    if (length < 2) detail::fail(path, "not a JPEG file (bad segment length)");
    const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      byte();  // sample precision
      const int height = byte() << 8 | byte();
      const int width = byte() << 8 | byte();
      if (width <= 0 || height <= 0) detail::fail(path, "bad JPEG size in the frame header");
      return {width, height};
    }
    f.seekg(length - 2, std::ios::cur);
  }
}

// The image file's size from its header; nullopt for a format whose header is not read.
std::optional<std::pair<int, int>> header_size(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".png") return detail::png_size(path);
  if (ext == ".jpg" || ext == ".jpeg") return jpeg_size(path);
  return std::nullopt;
}

}  // namespace

void check_images(const Dataset& dataset, const std::vector<ViewSource>& sources, Problems& problems,
                  DatasetSummary& summary) {
  struct VideoProbe {
    bool probed = false, size_checked = false;
    std::optional<VideoInfo> info;  // unset when the video cannot be opened
  };
  std::map<fs::path, VideoProbe> videos;
  std::map<std::string, size_t> unread;  // extension -> images whose size was not read
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    const View& v = dataset.views[k];
    const ViewSource& s = sources[k];
    const bool video = v.frame_in_file >= 0;
    const int ds = v.file_downscale > 0 ? v.file_downscale : std::max(1, dataset.downscale);
    if (!fs::exists(v.image)) {
      if (!s.image.empty()) problems.error(s.file, s.image, "image " + v.image.string() + " does not exist");
      else problems.error(v.image, "file", std::string(video ? "video" : "image") + " does not exist (view " + v.name + ")");
      continue;
    }
    std::optional<std::pair<int, int>> size;
    if (video) {
      VideoProbe& probe = videos[v.image];
      if (!probe.probed) {
        probe.probed = true;
        try {
          probe.info = probe_video(v.image);
        } catch (const std::exception& e) {
          problems.error(v.image, "file", e.what());
        }
      }
      if (!probe.info) continue;
      if (v.frame_in_file >= probe.info->frames) {
        problems.error(v.image, "frame " + std::to_string(v.frame_in_file),
                       "view " + v.name + " reads frame " + std::to_string(v.frame_in_file) + " but the video has " +
                           std::to_string(probe.info->frames) + " frames");
      }
      if (probe.size_checked) continue;
      probe.size_checked = true;
      size = std::pair{probe.info->width, probe.info->height};
    } else {
      try {
        size = header_size(v.image);
      } catch (const std::exception& e) {
        // png_size / jpeg_size say "<path>: <what>"; keep the what.
        std::string what = e.what();
        const std::string prefix = v.image.string() + ": ";
        if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
        problems.error(v.image, "file", what);
        continue;
      }
      if (!size) {
        ++unread[v.image.extension().string()];
        continue;
      }
    }
    const int w = size->first, h = size->second;
    const int cw = v.camera.width, ch = v.camera.height;
    if (w / ds != cw || h / ds != ch) {
      std::string expected = size_text(cw, ch);
      if (ds > 1) {
        expected += " at downscale " + std::to_string(ds) + ", which needs " + std::to_string(cw * ds) + ".." +
                    std::to_string(cw * ds + ds - 1) + " x " + std::to_string(ch * ds) + ".." +
                    std::to_string(ch * ds + ds - 1);
      }
      problems.error(v.image, "size",
                     "is " + size_text(w, h) + " but the view's camera (" + s.file.filename().string() + " " + s.pose +
                         ") is " + expected);
    }
  }
  for (const auto& [ext, count] : unread) {
    summary.notes.push_back("sizes of " + std::to_string(count) + " " + (ext.empty() ? "extension-less" : ext) +
                            " images not checked (only PNG and JPEG headers are read)");
  }
}

}  // namespace s4d::data::detail
