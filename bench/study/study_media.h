// The attention check's visibly broken video.
#pragma once
#include <cstdint>

#include "s4d/io/image_io.h"

namespace s4d::study {

// Corrupts frame `index` in place: blocks of random colour over about half of it, and every other
// run of 8 frames inverted, so that no participant paying attention can prefer it.
void corrupt_frame(io::ImageF& frame, int index, uint64_t seed);

}  // namespace s4d::study
