// 3DGS PLY reader (training/host/io/ply_gaussians.cpp) and the PLY header parser it uses.
#include "fuzz_common.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/io/ply_header.h"

S4D_FUZZ_TARGET(".ply", {
  try {
    const s4d::io::PlyHeader header = s4d::io::read_ply_header(path);
    (void)s4d::io::describe_ply_header(header);
  } catch (const std::exception&) {
  }
  const s4d::io::GaussianCloud cloud = s4d::io::read_ply_gaussians(path);
  (void)cloud.size();
})
