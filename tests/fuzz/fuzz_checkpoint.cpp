// Checkpoint container reader (training/runs/run/checkpoint.cpp). Only the file parsing is built: the
// arrays' names come from that file and header-only splat/gaussian_buffers.h, so no Vulkan code is linked.
#include "fuzz_common.h"
#include "s4d/run/checkpoint.h"

S4D_FUZZ_TARGET(".ckpt", {
  const s4d::run::Checkpoint checkpoint = s4d::run::read_checkpoint(path);
  (void)checkpoint.extra.size();
})
