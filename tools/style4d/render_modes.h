// The two modes of `style4d render`: a PLY from NeRF-style cameras, and a trained run's protocols.
// cmd_render.cpp parses the shared options and picks the mode.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "args.h"

namespace s4d::cli {

// --ply FILE --cameras transforms.json --out DIR [--background] [--sh-degree] [--size]
int render_ply(const Args& args);
// --run RUN --path test|spiral|train:CAM|FILE.json --out DIR [--style] [--format] [--spiral-frames] [--flow] [--background]
int render_run(const Args& args);

// "R,G,B" with three numbers; an error naming --background otherwise.
std::array<float, 3> parse_background(const std::string& text);

}  // namespace s4d::cli
