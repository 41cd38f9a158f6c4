#include "s4d/stylize/registry.h"

#include <stdexcept>

#include "s4d/stylize/patch_stylizer.h"

namespace s4d::stylize {

namespace {

// Network stylizers of the design (ARCHITECTURE.md stage 3, ALGORITHMS.md 4.2 and 5), not built yet.
const std::vector<std::string>& network_names() {
  static const std::vector<std::string> names = {"adain", "adaattn", "mccnet", "hgst"};
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::vector<std::string> stylizer_names() { return {"patch"}; }

std::unique_ptr<Stylizer> make_stylizer(const std::string& name) {
  if (name == "patch") return std::make_unique<PatchStylizer>();
  for (const std::string& n : network_names())
    if (n == name)
      throw std::invalid_argument("stylizer '" + name + "' needs --weights FILE and is not built yet (available: " +
                                  joined(stylizer_names()) + ")");
  throw std::invalid_argument("unknown stylizer '" + name + "' (available: " + joined(stylizer_names()) + ")");
}

}  // namespace s4d::stylize
