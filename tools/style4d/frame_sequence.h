// Whole frame sequences for `style4d stylize-frames` and the demo's videos: read by
// s4d/data/frame_reader.h (a folder of PNG frames sorted by name, or a video file), written as a
// folder of PNG files or a video.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::cli {

struct FrameSequence {
  std::vector<io::ImageF> frames;  // RGB
  std::vector<std::string> names;  // file names (NNNN.png for a video's frames)
};

// Every frame of data::FrameReader(path) with its name: the file's, or NNNN.png for a video's frame.
// Throws std::runtime_error naming the path when it is missing, holds no frames, or a frame cannot
// be read or differs in size from the first.
FrameSequence read_frame_sequence(const std::filesystem::path& path);

// A video path gets an mp4v video at 30 fps (see s4d/data/video_writer.h); any other path is a
// folder (created if needed) that receives one PNG per frame under `names`. Throws
// std::invalid_argument for no frames or a name count that differs from the frame count.
void write_frame_sequence(const std::filesystem::path& path, const std::vector<io::ImageF>& frames,
                          const std::vector<std::string>& names);

}  // namespace s4d::cli
