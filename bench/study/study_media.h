// The study's media from bench frame sequences: a browser-playable WebM video, single frames as
// PNG, and the attention check's visibly broken copy.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>

namespace s4d::study {

// Encodes the first `max_frames` frames of `sequence` (a PNG folder or a video) into `webm` at
// `fps` (odd sides padded by one edge row or column: 4:2:0 video needs even sides), and writes the
// frames named in `stills` (frame index -> PNG path) unchanged. With `broken_seed` != 0 every
// frame is corrupted first (blocks of noise, every other quarter-second inverted): the attention
// check's broken video. Returns the frames encoded.
int encode_sequence(const std::filesystem::path& sequence, int max_frames, double fps, const std::filesystem::path& webm,
                    const std::map<int, std::filesystem::path>& stills, uint64_t broken_seed = 0);

// The frames encode_sequence would encode (the sequence's count, capped at max_frames).
int sequence_frames(const std::filesystem::path& sequence, int max_frames);

}  // namespace s4d::study
