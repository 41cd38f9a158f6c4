// The DINO subject-consistency features of PNG frames, for dino_reference.py to compare with its
// PyTorch reference: per frame one line with the network input after dino_transform ([3, h, w]
// flattened, then h and w), one with the L2-normalised class token, as JSON arrays.
//   dino_features WEIGHTS.safetensors FRAME.png ...
#include <cstdio>
#include <exception>
#include <vector>

#include "s4d/metrics/dino_subject.h"
#include "s4d/io/image_file.h"

namespace {

template <class T>
void print(const std::vector<T>& v) {
  std::printf("[");
  for (size_t k = 0; k < v.size(); ++k) std::printf("%s%.9g", k ? "," : "", double(v[k]));
  std::printf("]\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: dino_features WEIGHTS.safetensors FRAME.png ...\n");
    return 2;
  }
  try {
    s4d::engine::Context ctx;  // ContextOptions::from_env(): S4D_VALIDATION, the device choice
    const s4d::metrics::DinoSubject dino(ctx, s4d::io::SafetensorsFile(argv[1]));
    for (int i = 2; i < argc; ++i) {
      const s4d::io::ImageF frame = s4d::io::read_image_rgb(argv[i]);
      s4d::util::Chw<float> input = s4d::metrics::dino_transform(frame);
      input.v.push_back(float(input.h));
      input.v.push_back(float(input.w));
      print(input.v);
      print(dino.features(frame));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dino_features: %s\n", e.what());
    return 1;
  }
  return 0;
}
