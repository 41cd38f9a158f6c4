// The captured frames behind the test protocol, laid out like its render (DIR/<camera>/NNNN.png) so
// the frames-mode evaluation reads them as ground truth for the psnr of the original-scene render.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/protocols/protocol.h"

namespace s4d::cli {

// Writes nothing and returns why when some frame of `sequences` has no test view of the same camera
// and time (D-NeRF: each test view's pose is captured at one time only); std::nullopt when written.
std::optional<std::string> write_ground_truth(const data::Dataset& dataset, const std::vector<protocols::Sequence>& sequences,
                                              const std::filesystem::path& dir);

}  // namespace s4d::cli
