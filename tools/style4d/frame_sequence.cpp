#include "frame_sequence.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "s4d/data/video_reader.h"
#include "s4d/data/video_writer.h"
#include "s4d/io/image_file.h"

namespace s4d::cli {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string frame_name(size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "%04zu.png", index);
  return name;
}

// Every frame the stream holds, whatever count the container declares.
FrameSequence read_video(const fs::path& path) {
  data::VideoReader video(path);
  FrameSequence seq;
  while (std::optional<io::ImageF> frame = video.next()) {
    seq.names.push_back(frame_name(seq.frames.size()));
    seq.frames.push_back(std::move(*frame));
  }
  if (seq.frames.empty()) throw std::runtime_error(path.string() + ": the video has no frames");
  return seq;
}

FrameSequence read_folder(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && lower(entry.path().extension().string()) == ".png") files.push_back(entry.path());
  if (files.empty()) throw std::runtime_error(dir.string() + ": no PNG frames in the folder");
  std::sort(files.begin(), files.end());
  FrameSequence seq;
  for (const fs::path& f : files) {
    seq.frames.push_back(io::read_image_rgb(f));
    seq.names.push_back(f.filename().string());
    if (seq.frames.back().width != seq.frames[0].width || seq.frames.back().height != seq.frames[0].height)
      throw std::runtime_error(f.string() + ": " + std::to_string(seq.frames.back().width) + "x" +
                               std::to_string(seq.frames.back().height) + ", but the first frame is " +
                               std::to_string(seq.frames[0].width) + "x" + std::to_string(seq.frames[0].height));
  }
  return seq;
}

}  // namespace

bool is_video_path(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  return ext == ".mp4" || ext == ".avi" || ext == ".mov" || ext == ".mkv";
}

FrameSequence read_frame_sequence(const fs::path& path) {
  if (fs::is_directory(path)) return read_folder(path);
  if (!fs::exists(path)) throw std::runtime_error(path.string() + ": no such folder or video");
  if (!is_video_path(path)) throw std::runtime_error(path.string() + ": neither a folder of PNG frames nor a video (.mp4, .avi, .mov, .mkv)");
  return read_video(path);
}

void write_frame_sequence(const fs::path& path, const std::vector<io::ImageF>& frames,
                          const std::vector<std::string>& names) {
  if (frames.empty() || names.size() != frames.size())
    throw std::invalid_argument(path.string() + ": needs at least one frame and one name per frame");
  if (is_video_path(path)) {
    data::VideoWriter writer(path, frames[0].width, frames[0].height);
    for (const io::ImageF& f : frames) writer.write(f);
    return;
  }
  fs::create_directories(path);
  for (size_t i = 0; i < frames.size(); ++i) io::write_png(path / names[i], frames[i]);
}

}  // namespace s4d::cli
