// Frames of a video file, decoded through OpenCV's FFmpeg backend as RGB float [H, W, 3] in [0, 1]:
// the DyNeRF / Neu3D camNN.mp4 videos, the videos `style4d stylize-frames` reads and the frames
// `style4d bench` scores. The one video reader of the project; OpenCV stays behind it (no public
// header includes OpenCV).
#pragma once
#include <filesystem>
#include <memory>
#include <optional>

#include "s4d/io/image_io.h"

namespace s4d::data {

struct VideoInfo {
  int width = 0, height = 0;
  int frames = 0;  // as the container declares it; decoding a frame past the real end fails then
};

// One open decoder over one video, remembering the frame it decodes next. Every error is a
// std::runtime_error("<path>: <problem>").
class VideoReader {
 public:
  // Throws when the file does not exist or cannot be opened as a video.
  explicit VideoReader(const std::filesystem::path& path);
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // The size and frame count the container declares; throws when either is missing or absurd.
  VideoInfo info() const;

  // The frame after the last one decoded (frame 0 first), or nothing when the stream ends there.
  // Throws for a frame that decodes to a pixel format other than 8-bit colour.
  std::optional<io::ImageF> next();

  // Frame `frame` (from 0). Reading frames in order never seeks; a short jump ahead decodes
  // forward, any other jump seeks. Throws naming the frame when it cannot be reached or decoded.
  io::ImageF read(int frame);

 private:
  struct Capture;
  std::filesystem::path path_;
  std::unique_ptr<Capture> capture_;
  int next_ = 0;  // the frame next() decodes
};

// VideoReader(path).info().
VideoInfo probe_video(const std::filesystem::path& path);

}  // namespace s4d::data
