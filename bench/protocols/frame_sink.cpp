#include "frame_sink.h"

#include <cstdio>

#include "s4d/data/video_writer.h"

namespace s4d::protocols {
namespace {

namespace fs = std::filesystem;

std::string numbered(int index, int frames, const char* ext) {
  int digits = 4;
  for (int n = frames - 1; n >= 10000; n /= 10) ++digits;
  char name[40];
  std::snprintf(name, sizeof name, "%0*d.%s", digits, index, ext);
  return name;
}

class PngSink final : public FrameSink {
 public:
  PngSink(fs::path dir, int frames) : dir_(std::move(dir)), frames_(frames) {}
  std::string write(int index, const io::ImageF& rgb, const std::vector<float>&, const std::vector<float>&) override {
    const std::string name = numbered(index, frames_, "png");
    io::write_png(dir_ / name, rgb);
    return name;
  }

 private:
  fs::path dir_;
  int frames_;
};

class ExrSink final : public FrameSink {
 public:
  ExrSink(fs::path dir, int frames) : dir_(std::move(dir)), frames_(frames) {}
  std::string write(int index, const io::ImageF& rgb, const std::vector<float>& alpha,
                    const std::vector<float>& depth) override {
    const size_t npix = alpha.size();
    std::vector<float> r(npix), g(npix), b(npix);
    for (size_t k = 0; k < npix; ++k) r[k] = rgb.data[3 * k], g[k] = rgb.data[3 * k + 1], b[k] = rgb.data[3 * k + 2];
    const std::string name = numbered(index, frames_, "exr");
    io::write_exr(dir_ / name, rgb.width, rgb.height,
                  {{"R", r.data()}, {"G", g.data()}, {"B", b.data()}, {"A", alpha.data()}, {"Z", depth.data()}});
    return name;
  }

 private:
  fs::path dir_;
  int frames_;
};

class Mp4Sink final : public FrameSink {
 public:
  Mp4Sink(const fs::path& dir, int width, int height, double fps) : video_(dir / kVideoName, width, height, fps) {}
  std::string write(int, const io::ImageF& rgb, const std::vector<float>&, const std::vector<float>&) override {
    video_.write(rgb);
    return "";
  }

 private:
  data::VideoWriter video_;
};

}  // namespace

std::unique_ptr<FrameSink> make_frame_sink(Format format, const fs::path& dir, int width, int height, int frames,
                                           double fps) {
  switch (format) {
    case Format::png: return std::make_unique<PngSink>(dir, frames);
    case Format::exr: return std::make_unique<ExrSink>(dir, frames);
    case Format::mp4: break;
  }
  return std::make_unique<Mp4Sink>(dir, width, height, fps);
}

std::string flow_file_name(const char* prefix, int pair) {
  char name[32];
  std::snprintf(name, sizeof name, "%s_%04d.exr", prefix, pair);
  return name;
}

}  // namespace s4d::protocols
