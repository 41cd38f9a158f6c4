// PNG reader (training/host/io/png_io.cpp, libpng underneath).
#include "fuzz_common.h"
#include "s4d/io/image_io.h"

S4D_FUZZ_TARGET(".png", {
  const s4d::io::ImageF image = s4d::io::read_png(path);
  (void)image.data.size();
})
