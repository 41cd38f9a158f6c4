// Renders a protocol's sequences from a scene source into an output folder, optionally with the
// renderer's exact optical flow between consecutive frames.
//
// Layout of DIR (the folder given): a path with one sequence (spiral, train:CAM) writes it into DIR
// itself; `test` writes each test camera's sequence into DIR/<camera name>/. A sequence folder holds
//   NNNN.png | NNNN.exr | video.mp4   the frames (PNG: RGB over the background; EXR: R, G, B, A =
//                                     accumulated alpha, Z = expected depth; mp4: OpenCV mp4v, lossy,
//                                     even sizes only)
//   flow/fw_NNNN.exr, flow/bw_NNNN.exr   with flow on: for the pair (k, k+1), forward flow rendered at
//                                     frame k (k -> k+1) and backward flow rendered at frame k+1
//                                     (k+1 -> k); channels u and v in pixels (the warp loss's files)
// and DIR/frames.json (frames_json.h) lists every sequence and frame.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/protocols/frames_json.h"
#include "s4d/protocols/protocol.h"
#include "s4d/scene/scene_source.h"

namespace s4d::protocols {

enum class Format { png, exr, mp4 };

inline constexpr const char* kVideoName = "video.mp4";

// "png", "exr" or "mp4"; std::invalid_argument otherwise.
Format parse_format(const std::string& text);
std::string format_name(Format format);

struct RenderOptions {
  Format format = Format::png;
  bool flow = false;
  std::array<float, 3> background{0, 0, 0};
  double fps = 30;  // mp4 only
};

struct SequenceStats {
  std::string name;
  int frames = 0;
  double ms_render = 0;  // mean GPU render + readback per frame
  double ms_flow = 0;    // mean per frame for both flows, 0 without flow
  uint32_t max_instances = 0;
};

struct ProtocolResult {
  FramesRecord record;  // also written as DIR/frames.json
  std::vector<SequenceStats> stats;
};

// "fw_0012.exr": the name of a pair's flow file in a sequence's flow/ (the names bench/metrics reads,
// frames_eval.cpp).
std::string flow_file_name(const char* prefix, int pair);

// Throws std::invalid_argument before writing anything when `out` exists and is not an empty folder,
// a sequence is empty, or mp4 is asked for an odd frame size; rendering and file errors propagate.
ProtocolResult render_protocol(engine::Context& ctx, scene::SceneSource& scene, const PathSpec& path,
                               const std::vector<Sequence>& sequences, const std::filesystem::path& out,
                               const RenderOptions& options);

}  // namespace s4d::protocols
