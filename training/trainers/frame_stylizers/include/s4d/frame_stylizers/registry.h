// Stylizers by name, for the command line and the pipeline's settings.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "s4d/frame_stylizers/network_stylizer.h"
#include "s4d/frame_stylizers/stylizer.h"

namespace s4d::frame_stylizers {

// The names make_stylizer accepts, the default ("patch") first.
std::vector<std::string> stylizer_names();

// Throws std::invalid_argument for an unknown name, listing the available ones; for a network
// stylizer without `network.weights`, saying which files it needs; and for "patch" with weights.
// Network stylizers load their weights here, so a bad weight file fails before any frame is read
// (network_stylizer.h).
std::unique_ptr<Stylizer> make_stylizer(const std::string& name, const NetworkOptions& network = {});

}  // namespace s4d::frame_stylizers
