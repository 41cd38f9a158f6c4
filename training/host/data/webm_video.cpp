#include "s4d/data/webm_video.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "s4d/data/frame_reader.h"
#include "s4d/data/video_writer.h"

namespace s4d::data {

namespace {

io::ImageF even_sides(const io::ImageF& im) {
  const int w = im.width + im.width % 2, h = im.height + im.height % 2;
  if (w == im.width && h == im.height) return im;
  io::ImageF out{w, h, 3, std::vector<float>(static_cast<size_t>(w) * h * 3)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        out.data[(static_cast<size_t>(y) * w + x) * 3 + c] =
            im.data[(static_cast<size_t>(std::min(y, im.height - 1)) * im.width + std::min(x, im.width - 1)) * 3 + c];
  return out;
}

}  // namespace

int webm_frame_count(const std::filesystem::path& sequence, int max_frames) {
  return std::min(FrameReader(sequence).size(), max_frames);
}

int encode_webm(const std::filesystem::path& sequence, int max_frames, double fps, const std::filesystem::path& webm,
                const std::function<void(int, io::ImageF&)>& each_frame) {
  FrameReader reader(sequence);
  const int n = std::min(reader.size(), max_frames);
  if (n == 0) throw std::runtime_error(sequence.string() + ": no frames");
  if (webm.has_parent_path()) std::filesystem::create_directories(webm.parent_path());
  std::unique_ptr<VideoWriter> writer;
  for (int k = 0; k < n; ++k) {
    io::ImageF frame = reader.next_counted();
    if (each_frame) each_frame(k, frame);
    const io::ImageF even = even_sides(frame);
    if (!writer) writer = std::make_unique<VideoWriter>(webm, even.width, even.height, fps);
    writer->write(even);
  }
  return n;
}

}  // namespace s4d::data
