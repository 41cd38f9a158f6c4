// Writes RGB frames into an .mp4 video, the DyNeRF / Neu3D camNN.mp4 layout, with OpenCV's FFmpeg
// backend and the MPEG-4 Part 2 encoder (fourcc mp4v), the one every FFmpeg build has; or, for a
// path ending in .webm, VP9 in WebM (FFmpeg's libvpx), which browsers play: Chromium plays no mp4v.
// mp4v is lossy: 8 bits per channel, chroma at half resolution (4:2:0), about 1 bit per pixel (OpenCV 4.6
// offers no quality setting for it), so decoded frames differ from the written ones: by about 3 levels
// of 255 on average on smooth content, 6-11 on the synthetic scene's textures, more at sharp edges.
#pragma once
#include <filesystem>
#include <memory>

#include "s4d/io/image_io.h"

namespace s4d::data {

class VideoWriter {
 public:
  // Throws std::invalid_argument for an odd width or height (4:2:0 needs even sides; the encoder
  // would silently drop the last row or column) or fps <= 0, std::runtime_error naming the file when
  // the encoder cannot be opened (OpenCV without FFmpeg or without the encoder, or an unwritable path).
  VideoWriter(const std::filesystem::path& path, int width, int height, double fps = 30);
  ~VideoWriter();  // finishes the file
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Appends one RGB frame [H, W, 3]; values are clamped to [0, 1] and rounded to 8 bits. Throws
  // std::invalid_argument naming the file when the frame's shape is not the video's.
  void write(const io::ImageF& rgb);

 private:
  struct Encoder;
  std::filesystem::path path_;
  int width_, height_;
  std::unique_ptr<Encoder> encoder_;
};

}  // namespace s4d::data
