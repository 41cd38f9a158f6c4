// NeRF / D-NeRF transforms.json reader (training/host/io/nerf_cameras.cpp), with and without a default size.
#include "fuzz_common.h"
#include "s4d/io/nerf_cameras.h"

S4D_FUZZ_TARGET(".json", {
  try {
    (void)s4d::io::read_nerf_cameras(path);
  } catch (const std::exception&) {
  }
  (void)s4d::io::read_nerf_cameras(path, std::pair<int, int>{8, 6});
})
