// The two modes of `style4d render`: a PLY from NeRF-style cameras, and a trained run's protocols.
// cmd_render.cpp parses the shared options and picks the mode.
#pragma once
#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "args.h"
#include "s4d/engine/context.h"
#include "s4d/splat/gaussian_buffers.h"

namespace s4d::cli {

// --ply FILE --cameras transforms.json --out DIR [--background] [--sh-degree] [--size] [--half]
int render_ply(const Args& args);
// --run RUN --path test|spiral|train:CAM|FILE.json --out DIR [--style] [--format] [--spiral-frames] [--flow] [--background] [--half]
int render_run(const Args& args);

// "R,G,B" with three numbers; an error naming --background otherwise.
std::array<float, 3> parse_background(const std::string& text);

// render.json's "storage": "f32" or "f16" (--half), the bytes of the device's SH and style MLP
// storage, and the most device memory this process's buffers held.
nlohmann::json storage_json(splat::Storage storage, size_t sh_style_bytes, const engine::Context& ctx);

}  // namespace s4d::cli
