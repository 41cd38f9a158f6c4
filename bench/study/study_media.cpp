#include "study_media.h"

#include <algorithm>
#include <stdexcept>

#include "s4d/data/frame_reader.h"
#include "s4d/data/video_writer.h"
#include "s4d/io/image_io.h"

namespace s4d::study {

namespace {

uint64_t splitmix(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Blocks of random colour over about half of the frame, and every other 8-frame run inverted: no
// participant paying attention can prefer it.
void corrupt(io::ImageF& im, int frame, uint64_t seed) {
  uint64_t state = seed * 1000003u + static_cast<uint64_t>(frame);
  const int block = std::max(2, std::min(im.width, im.height) / 6);
  const bool invert = (frame / 8) % 2 == 1;
  for (int by = 0; by < im.height; by += block)
    for (int bx = 0; bx < im.width; bx += block) {
      const uint64_t r = splitmix(state);
      const bool noise = (r & 1) != 0;
      for (int y = by; y < std::min(by + block, im.height); ++y)
        for (int x = bx; x < std::min(bx + block, im.width); ++x)
          for (int c = 0; c < 3; ++c) {
            float& v = im.data[(static_cast<size_t>(y) * im.width + x) * 3 + c];
            if (noise) v = static_cast<float>((r >> (8 + 8 * c)) & 0xff) / 255.0f;
            else if (invert) v = 1.0f - v;
          }
    }
}

// The frame with its last column and/or row repeated to make both sides even.
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

int sequence_frames(const std::filesystem::path& sequence, int max_frames) {
  return std::min(data::FrameReader(sequence).size(), max_frames);
}

int encode_sequence(const std::filesystem::path& sequence, int max_frames, double fps, const std::filesystem::path& webm,
                    const std::map<int, std::filesystem::path>& stills, uint64_t broken_seed) {
  data::FrameReader reader(sequence);
  const int n = std::min(reader.size(), max_frames);
  std::filesystem::create_directories(webm.parent_path());
  std::unique_ptr<data::VideoWriter> writer;
  for (int k = 0; k < n; ++k) {
    io::ImageF frame = reader.next_counted();
    if (broken_seed != 0) corrupt(frame, k, broken_seed);
    if (auto it = stills.find(k); it != stills.end()) io::write_png(it->second, frame);
    const io::ImageF even = even_sides(frame);
    if (!writer) writer = std::make_unique<data::VideoWriter>(webm, even.width, even.height, fps);
    writer->write(even);
  }
  if (n == 0) throw std::runtime_error(sequence.string() + ": no frames");
  return n;
}

}  // namespace s4d::study
