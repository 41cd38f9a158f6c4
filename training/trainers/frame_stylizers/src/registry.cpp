#include "s4d/frame_stylizers/registry.h"

#include <algorithm>
#include <stdexcept>

#include "s4d/frame_stylizers/patch_stylizer.h"

namespace s4d::frame_stylizers {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::vector<std::string> stylizer_names() {
  std::vector<std::string> names = {"patch"};
  for (const std::string& n : network_stylizer_names()) names.push_back(n);
  return names;
}

std::unique_ptr<Stylizer> make_stylizer(const std::string& name, const NetworkOptions& network) {
  const auto networks = network_stylizer_names();
  if (name == "patch") {
    if (!network.weights.empty())
      throw std::invalid_argument("patch needs no weights; --weights is for " + joined(networks));
    return std::make_unique<PatchStylizer>();
  }
  if (std::find(networks.begin(), networks.end(), name) != networks.end()) return make_network_stylizer(name, network);
  throw std::invalid_argument("unknown stylizer '" + name + "' (available: " + joined(stylizer_names()) + ")");
}

}  // namespace s4d::frame_stylizers
