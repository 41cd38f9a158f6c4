// safetensors reader (training/host/io/safetensors.cpp): the header, then every tensor at its own shape.
#include "fuzz_common.h"
#include "s4d/io/safetensors.h"

S4D_FUZZ_TARGET(".safetensors", {
  const s4d::io::SafetensorsFile file(path);
  (void)file.metadata().size();
  for (const std::string& name : file.names()) {
    try {
      (void)file.read(name, file.shape(name));
    } catch (const std::exception&) {
    }
  }
})
