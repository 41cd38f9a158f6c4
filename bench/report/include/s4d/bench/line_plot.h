// Simple line plots drawn with OpenCV: axes, ticks with values, axis labels, a title and a legend,
// one coloured line per series. Written as PNG.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::bench {

struct Series {
  std::string name;
  std::vector<double> values;  // y at x = 0, 1, 2, ...
};

// An RGB image of the plot (800x450). Throws std::invalid_argument when there is no series or a
// series has no value.
io::ImageF line_plot(const std::string& title, const std::string& x_label, const std::string& y_label,
                     const std::vector<Series>& series);

}  // namespace s4d::bench
