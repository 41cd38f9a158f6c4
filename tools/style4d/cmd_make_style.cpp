// style4d make-style --out F.png [--size N] [--seed S]: writes the built-in procedural style image
// (assets/styles/builtin.png is the default size and seed).
#include <cstdint>
#include <iostream>
#include <stdexcept>

#include "args.h"
#include "commands.h"
#include "s4d/frame_stylizers/builtin_style.h"
#include "s4d/util/free_memory.h"

namespace s4d::cli {

int cmd_make_style(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"out", "the PNG to write", true, "F.png"},
      {"size", "side in pixels, at least 32 (default 384)", true, "N"},
      {"seed", "seed of the strokes and the colour zones (default 0)", true, "S"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("make-style", "--out F.png [--size N] [--seed S]",
                       "Writes the built-in style: a procedural painting (swirling brush strokes of a fixed palette\n"
                       "over a canvas weave). The defaults reproduce assets/styles/builtin.png.",
                       specs);
    return 0;
  }
  if (!args.positionals().empty()) throw UsageError("unexpected argument '" + args.positionals().front() + "'");
  const std::string out = args.require("out");
  const int size = parse_number<int>("size", args.get_or("size", "384"));
  if (size < 32) throw UsageError("--size: " + std::to_string(size) + " is below 32");
  const uint64_t seed = parse_number<uint64_t>("seed", args.get_or("seed", "0"));
  // The canvas, the image and the PNG's rows (3 + 3 floats and 3 bytes a pixel, the encoded file beside).
  const uint64_t pixels = uint64_t(size) * uint64_t(size);
  util::require_memory("--size " + std::to_string(size), pixels * 30, "painting " + std::to_string(size) + "x" +
                       std::to_string(size) + " pixels");
  io::write_png(out, frame_stylizers::builtin_style(size, seed));
  std::cout << "wrote " << out << " (" << size << "x" << size << ")\n";
  return 0;
}

}  // namespace s4d::cli
