// Stylizers by name, for the command line and the pipeline's settings.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "s4d/stylize/stylizer.h"

namespace s4d::stylize {

// The names make_stylizer accepts, the default ("patch") first.
std::vector<std::string> stylizer_names();

// Throws std::invalid_argument for an unknown name, listing the available ones; for a network
// stylizer of the design (adain, adaattn, mccnet, hgst) it says that it needs weights and is not
// built yet.
std::unique_ptr<Stylizer> make_stylizer(const std::string& name);

}  // namespace s4d::stylize
