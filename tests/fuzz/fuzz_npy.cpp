// NumPy .npy reader (training/host/data/npy.cpp).
#include "fuzz_common.h"
#include "s4d/data/npy.h"

S4D_FUZZ_TARGET(".npy", {
  const s4d::data::NpyArray array = s4d::data::read_npy(path);
  (void)array.values.size();
})
