// The protocol render loop. Per frame k the source is asked for time t_k (and, with flow, t_{k+1}
// first, for the next frame's screen positions); the image is rendered, then the forward flow of the
// pair (k, k+1) and the backward flow of the pair (k-1, k), both at frame k (exact_flow.h).
#include "s4d/protocols/protocol_render.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "frame_sink.h"
#include "s4d/engine/buffer.h"
#include "s4d/splat/exact_flow.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/util/progress.h"

namespace s4d::protocols {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

void check_inputs(const std::vector<Sequence>& sequences, const fs::path& out, const RenderOptions& o) {
  if (fs::exists(out) && !(fs::is_directory(out) && fs::is_empty(out)))
    throw std::invalid_argument(out.string() + " already exists and is not an empty folder; choose a new --out");
  if (sequences.empty()) throw std::invalid_argument("render: the protocol has no sequences");
  for (const Sequence& s : sequences) {
    if (s.frames.empty()) throw std::invalid_argument("render: sequence " + s.name + " has no frames");
    const io::CameraView& c = s.frames.front().camera;
    if (o.format == Format::mp4 && (c.width % 2 != 0 || c.height % 2 != 0))
      throw std::invalid_argument("render: mp4 needs even frame sizes (4:2:0 chroma) but sequence " + s.name + " is " +
                                  std::to_string(c.width) + "x" + std::to_string(c.height) + "; use --format png or exr");
  }
}

void write_flow(const fs::path& file, const splat::FlowImage& f) {
  io::write_exr(file, int(f.width), int(f.height), {{"u", f.u.data()}, {"v", f.v.data()}});
}

// Expected depth: the alpha-weighted depth sum over the accumulated alpha, 0 where nothing blended.
std::vector<float> expected_depth(const std::vector<float>& depth_sum, const std::vector<float>& alpha) {
  std::vector<float> z(depth_sum.size(), 0.0f);
  for (size_t k = 0; k < z.size(); ++k)
    if (alpha[k] > 1e-6f) z[k] = depth_sum[k] / alpha[k];
  return z;
}

class SequenceRenderer {
 public:
  SequenceRenderer(engine::Context& ctx, scene::SceneSource& scene, const RenderOptions& o)
      : ctx_(ctx), scene_(scene), o_(o), raster_(ctx, "protocol") {
    if (o.flow) {
      const size_t bytes = std::max<size_t>(1, scene.size()) * 12;
      for (int s = 0; s < 3; ++s) screen_[s] = engine::Buffer(ctx, "flow screen " + std::to_string(s), bytes);
      displacement_ = engine::Buffer(ctx, "flow displacement", bytes);
    }
  }

  SequenceStats render(const Sequence& seq, const fs::path& dir, SequenceRecord& rec, util::Progress& progress,
                       uint64_t& done) {
    fs::create_directories(dir);
    if (o_.flow) fs::create_directories(dir / "flow");
    const int n = static_cast<int>(seq.frames.size());
    const io::CameraView& first = seq.frames.front().camera;
    std::unique_ptr<FrameSink> sink = make_frame_sink(o_.format, dir, first.width, first.height, n, o_.fps);
    SequenceStats st{seq.name, n, 0, 0, 0};
    int prev = 0, cur = 1, next = 2;  // screen lane slots of frames k-1, k, k+1
    for (int k = 0; k < n; ++k) {
      const ProtocolFrame& f = seq.frames[k];
      const splat::Camera cam = splat::to_splat_camera(f.camera);
      auto t0 = Clock::now();
      if (o_.flow) {
        if (k == 0) splat::project_means(ctx_, scene_.at(f.time, cam), cam, screen_[cur]);
        if (k + 1 < n) {
          const splat::Camera cam_next = splat::to_splat_camera(seq.frames[k + 1].camera);
          splat::project_means(ctx_, scene_.at(seq.frames[k + 1].time, cam_next), cam_next, screen_[next]);
        }
      }
      const splat::GaussianParams g = scene_.at(f.time, cam);
      const splat::RenderStats rs = raster_.forward(g, cam, o_.background);
      const size_t npix = size_t{cam.width} * cam.height;
      const io::ImageF rgb{int(cam.width), int(cam.height), 3, ctx_.download<float>(raster_.rgb(), 3 * npix)};
      const std::vector<float> alpha = ctx_.download<float>(raster_.alpha(), npix);
      const std::vector<float> depth = expected_depth(ctx_.download<float>(raster_.depth(), npix), alpha);
      st.ms_render += ms_since(t0) / n;
      st.max_instances = std::max(st.max_instances, rs.instances);
      rec.files.push_back(sink->write(k, rgb, alpha, depth));
      if (o_.flow) {
        t0 = Clock::now();
        const uint32_t count = scene_.size();
        if (k + 1 < n) {
          splat::screen_displacement(ctx_, screen_[cur], screen_[next], count, displacement_);
          write_flow(dir / "flow" / flow_file_name("fw", k), splat::render_flow(raster_, g, displacement_, cam));
        }
        if (k > 0) {
          splat::screen_displacement(ctx_, screen_[cur], screen_[prev], count, displacement_);
          write_flow(dir / "flow" / flow_file_name("bw", k - 1), splat::render_flow(raster_, g, displacement_, cam));
        }
        st.ms_flow += ms_since(t0) / n;
        std::tie(prev, cur, next) = std::make_tuple(cur, next, prev);
      }
      progress.update(++done, {{"ms", st.ms_render}});
    }
    return st;
  }

 private:
  engine::Context& ctx_;
  scene::SceneSource& scene_;
  const RenderOptions& o_;
  splat::Rasterizer raster_;
  engine::Buffer screen_[3], displacement_;
};

}  // namespace

Format parse_format(const std::string& text) {
  if (text == "png") return Format::png;
  if (text == "exr") return Format::exr;
  if (text == "mp4") return Format::mp4;
  throw std::invalid_argument("--format: expected png, exr or mp4, got '" + text + "'");
}

std::string format_name(Format format) {
  switch (format) {
    case Format::png: return "png";
    case Format::exr: return "exr";
    case Format::mp4: break;
  }
  return "mp4";
}

ProtocolResult render_protocol(engine::Context& ctx, scene::SceneSource& scene, const PathSpec& path,
                               const std::vector<Sequence>& sequences, const fs::path& out, const RenderOptions& o) {
  check_inputs(sequences, out, o);
  fs::create_directories(out);
  const bool one = path.kind != PathSpec::Kind::test;
  uint64_t total = 0, done = 0;
  for (const Sequence& s : sequences) total += s.frames.size();
  util::Progress progress("render", total);
  SequenceRenderer renderer(ctx, scene, o);
  ProtocolResult result{{path.text(), format_name(o.format), {}}, {}};
  for (const Sequence& s : sequences) {
    SequenceRecord rec{s, one ? "." : s.name, o.format == Format::mp4 ? kVideoName : "", {}, o.flow};
    result.stats.push_back(renderer.render(s, one ? out : out / s.name, rec, progress, done));
    result.record.sequences.push_back(std::move(rec));
  }
  progress.finish({});
  write_frames_json(out / "frames.json", result.record);
  return result;
}

}  // namespace s4d::protocols
