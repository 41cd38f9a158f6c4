// Checkpoint container reader (training/run/checkpoint.cpp). Only the file parsing is built: the
// model's attribute names come from a file generated out of training/model/trainable_gaussians.cpp
// (tests/fuzz/CMakeLists.txt), so no Vulkan code is linked.
#include "fuzz_common.h"
#include "s4d/run/checkpoint.h"

S4D_FUZZ_TARGET(".ckpt", {
  const s4d::run::Checkpoint checkpoint = s4d::run::read_checkpoint(path);
  (void)checkpoint.extra.size();
})
