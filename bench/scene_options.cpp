#include "scene_options.h"

#include <sstream>
#include <stdexcept>

namespace s4d::bench {

const std::vector<SplatPoint> kPeerSuite = {{128, 128, 1000}, {256, 256, 10000}, {512, 512, 100000}};

SplatPoint parse_point(const std::string& s) {
  const size_t x = s.find('x'), colon = s.find(':');
  if (x == std::string::npos || colon == std::string::npos || colon < x)
    throw std::invalid_argument("size '" + s + "' is not WxH:N");
  return {.width = static_cast<uint32_t>(std::stoul(s.substr(0, x))),
          .height = static_cast<uint32_t>(std::stoul(s.substr(x + 1, colon - x - 1))),
          .gaussians = static_cast<uint32_t>(std::stoul(s.substr(colon + 1)))};
}

bool parse_scene_option(int argc, char** argv, int& i, SceneOptions& o) {
  const std::string a = argv[i], value = i + 1 < argc ? argv[i + 1] : "";
  if (a == "--suite" && value == "peer") {
    o.peer_suite = true;
  } else if (value.empty() ||
             (a != "--sizes" && a != "--ply" && a != "--cameras" && a != "--camera" && a != "--bwd-pixels" &&
              a != "--fwd-pixels")) {
    return false;
  } else if (a == "--sizes") {
    o.points.clear();
    std::stringstream ss(value);
    for (std::string tok; std::getline(ss, tok, ',');) o.points.push_back(parse_point(tok));
  } else if (a == "--ply") {
    o.ply = value;
  } else if (a == "--cameras") {
    o.cameras = value;
  } else if (a == "--bwd-pixels") {
    o.bwd_pixels = static_cast<uint32_t>(std::stoul(value));
  } else if (a == "--fwd-pixels") {
    o.fwd_pixels = static_cast<uint32_t>(std::stoul(value));
  } else {
    o.camera = std::stoul(value);
  }
  ++i;
  return true;
}

void check_scene_options(const SceneOptions& o) {
  if (o.points.empty() && o.ply.empty() && !o.peer_suite) throw std::invalid_argument("need at least one size");
  if (o.ply.empty() != o.cameras.empty()) throw std::invalid_argument("--ply and --cameras go together");
  if (!o.ply.empty() && o.peer_suite) throw std::invalid_argument("--ply and --suite exclude each other");
}

}  // namespace s4d::bench
