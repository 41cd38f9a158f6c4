#include "s4d/stylize/registry.h"

#include <stdexcept>

#include "s4d/stylize/patch_stylizer.h"

namespace s4d::stylize {

namespace {

// Network stylizers of the design (ARCHITECTURE.md stage 3, ALGORITHMS.md 4.2 and 5), not built yet.
const std::vector<std::string>& unbuilt_names() {
  static const std::vector<std::string> names = {"adaattn", "mccnet", "hgst"};
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::vector<std::string> stylizer_names() { return {"patch", "adain"}; }

std::unique_ptr<Stylizer> make_stylizer(const std::string& name, const NetworkOptions& network) {
  if (name == "patch") {
    if (!network.weights.empty()) throw std::invalid_argument("patch needs no weights; --weights is for adain");
    return std::make_unique<PatchStylizer>();
  }
  if (name == "adain") return std::make_unique<AdainStylizer>(network);
  for (const std::string& n : unbuilt_names())
    if (n == name)
      throw std::invalid_argument("stylizer '" + name + "' is not built yet (available: " + joined(stylizer_names()) +
                                  ")");
  throw std::invalid_argument("unknown stylizer '" + name + "' (available: " + joined(stylizer_names()) + ")");
}

}  // namespace s4d::stylize
