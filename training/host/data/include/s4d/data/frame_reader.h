// The frames of one sequence on disk, front to back: a folder of PNG frames (sorted by file name)
// or a video file (read by s4d/data/video_reader.h). The one reader of frame sequences: `style4d
// stylize-frames` (and the demo's videos), the bench's frames mode and its pyiqa bridge.
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::data {

class VideoReader;

// .mp4, .avi, .mov or .mkv, in any case.
bool is_video_path(const std::filesystem::path& path);

// The PNG files of a frame folder (extension .png in any case), sorted by name. Throws
// std::runtime_error naming the folder when it holds none.
std::vector<std::filesystem::path> png_frames(const std::filesystem::path& folder);

class FrameReader {
 public:
  // Throws std::runtime_error naming the path when it is missing, a folder without PNG frames, a
  // file that is not a video by its extension, or a video that cannot be opened.
  explicit FrameReader(const std::filesystem::path& path);
  ~FrameReader();
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;

  // The folder's PNG files in reading order; empty for a video.
  const std::vector<std::filesystem::path>& files() const { return pngs_; }
  // Frames: the folder's PNG count, or the count the video's container declares.
  int size() const { return count_; }

  // The next frame as RGB [H, W, 3] in [0, 1] (a PNG's gray is replicated, its alpha dropped; 8-bit
  // levels v / 255, 16-bit v / 65535), or nothing after the last one: the folder's last file, or
  // the end of the video's stream, whatever count its container declares. Throws
  // std::runtime_error naming the file (or video and frame) when a frame cannot be read or differs
  // in size from the first.
  std::optional<io::ImageF> next();
  // next() for a caller that reads size() frames: throws std::runtime_error naming the path when
  // none is left (a video whose stream ends before the count its container declares).
  io::ImageF next_counted();

 private:
  std::filesystem::path path_;
  std::vector<std::filesystem::path> pngs_;
  std::unique_ptr<VideoReader> video_;
  int count_ = 0, next_ = 0;
  int width_ = 0, height_ = 0;  // the first frame's
};

}  // namespace s4d::data
