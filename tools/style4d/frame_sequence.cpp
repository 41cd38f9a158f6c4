#include "frame_sequence.h"

#include <cstdio>
#include <optional>
#include <stdexcept>

#include "s4d/data/frame_reader.h"
#include "s4d/data/video_writer.h"

namespace s4d::cli {

namespace fs = std::filesystem;

namespace {

std::string frame_name(size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "%04zu.png", index);
  return name;
}

}  // namespace

FrameSequence read_frame_sequence(const fs::path& path) {
  data::FrameReader reader(path);
  FrameSequence seq;
  while (std::optional<io::ImageF> frame = reader.next()) {
    seq.names.push_back(reader.files().empty() ? frame_name(seq.frames.size())
                                               : reader.files()[seq.frames.size()].filename().string());
    seq.frames.push_back(std::move(*frame));
  }
  if (seq.frames.empty()) throw std::runtime_error(path.string() + ": the video has no frames");
  return seq;
}

void write_frame_sequence(const fs::path& path, const std::vector<io::ImageF>& frames,
                          const std::vector<std::string>& names) {
  if (frames.empty() || names.size() != frames.size())
    throw std::invalid_argument(path.string() + ": needs at least one frame and one name per frame");
  if (data::is_video_path(path)) {
    data::VideoWriter writer(path, frames[0].width, frames[0].height);
    for (const io::ImageF& f : frames) writer.write(f);
    return;
  }
  fs::create_directories(path);
  for (size_t i = 0; i < frames.size(); ++i) io::write_png(path / names[i], frames[i]);
}

}  // namespace s4d::cli
