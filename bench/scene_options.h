// The scene options the splat benches share (the like-for-like runs against the peer): --sizes WxH:N,...,
// --ply F --cameras transforms.json [--camera K] (a standard 3DGS scene), --suite peer, and
// --bwd-pixels 1|8 and --fwd-pixels 1|8 (the rasterizer's variants, RasterizerOptions::backward_pixels
// and forward_pixels).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "splat_bench.h"

namespace s4d::bench {

// The PyTorch peer's sizes.
extern const std::vector<SplatPoint> kPeerSuite;

struct SceneOptions {
  std::vector<SplatPoint> points;  // --sizes
  std::string ply, cameras;
  size_t camera = 0;
  bool peer_suite = false;
  uint32_t bwd_pixels = 0;  // --bwd-pixels 1|8: the backward kernel's variant (0: by device type)
  uint32_t fwd_pixels = 0;  // --fwd-pixels 1|8: the forward kernel's variant (0: by device type)
};

// "WxH:N" -> point; throws std::invalid_argument on anything else.
SplatPoint parse_point(const std::string& s);
// Takes argv[i] (and its value, advancing i) when it is a scene option; false when it is not one.
bool parse_scene_option(int argc, char** argv, int& i, SceneOptions& o);
// Throws std::invalid_argument when the scene options contradict each other.
void check_scene_options(const SceneOptions& o);

}  // namespace s4d::bench
