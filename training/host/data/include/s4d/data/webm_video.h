// A frame sequence (a PNG folder or a video) as a browser-playable WebM (VP9) video: what the study
// pages and report.html play. Chromium plays no mp4v, the bench's .mp4 encoder.
#pragma once
#include <filesystem>
#include <functional>

#include "s4d/io/image_io.h"

namespace s4d::data {

// The frames encode_webm would encode: the sequence's count, capped at max_frames.
int webm_frame_count(const std::filesystem::path& sequence, int max_frames);

// Encodes the first `max_frames` frames of `sequence` into `webm` at `fps`; odd sides are padded by
// repeating the last row or column (4:2:0 video needs even sides). `each_frame(index, frame)` sees
// (and may change) every frame before it is encoded. Returns the frames encoded; throws
// std::runtime_error naming the file when a frame cannot be read or the video written.
int encode_webm(const std::filesystem::path& sequence, int max_frames, double fps, const std::filesystem::path& webm,
                const std::function<void(int, io::ImageF&)>& each_frame = {});

}  // namespace s4d::data
