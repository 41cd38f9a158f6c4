// DIR/frames.json: every rendered frame with its time and camera, so a later step (metrics, another
// renderer, a re-render) reproduces exactly what was drawn. Layout:
//   {"path": "spiral", "format": "png",
//    "sequences": [{"name": "spiral", "dir": ".", "video": "",          // "video.mp4" for mp4 output
//                   "flow": true,                                       // dir/flow/{fw,bw}_NNNN.exr
//                   "frames": [{"index": 0, "time": 0.0, "file": "0000.png",  // "" in a video
//                               "width": 48, "height": 36, "fx": .., "fy": .., "cx": .., "cy": ..,
//                               "world_to_cam": [[r00, r01, r02, t0], [..], [..], [0, 0, 0, 1]]}]}]}
// world_to_cam is row-major, OpenCV axes (x right, y down, z forward), pixel centres at +0.5.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/protocols/protocol.h"

namespace s4d::protocols {

struct SequenceRecord {
  Sequence sequence;
  std::string dir;                 // relative to frames.json's folder: "." or the sequence name
  std::string video;               // "video.mp4" for mp4 output, else empty
  std::vector<std::string> files;  // per frame, relative to dir; empty strings in a video
  bool flow = false;               // dir/flow/fw_NNNN.exr and bw_NNNN.exr exist for every pair
};

struct FramesRecord {
  std::string path;    // PathSpec::text()
  std::string format;  // "png", "exr" or "mp4"
  std::vector<SequenceRecord> sequences;
};

// Replaces `file` atomically.
void write_frames_json(const std::filesystem::path& file, const FramesRecord& record);

// Throws std::runtime_error naming the file and the field that is missing or malformed.
FramesRecord read_frames_json(const std::filesystem::path& file);

}  // namespace s4d::protocols
