// A contact sheet of sample frames: one row for the original render and one per method, one column
// per sample frame, each tile scaled to a fixed width, labelled with the row name and frame index.
#pragma once
#include <string>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::bench {

struct SheetRow {
  std::string label;
  std::vector<io::ImageF> frames;  // RGB, all rows the same count
};

// Throws std::invalid_argument when there are no rows or the rows differ in frame count.
io::ImageF contact_sheet(const std::vector<SheetRow>& rows, const std::vector<int>& frame_index, int tile_width = 256);

}  // namespace s4d::bench
