// The shape and loop-count checks that layers.cpp and layers_grad.cpp make before recording.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

#include "s4d_nn.h"

namespace s4d::nn::detail {

[[noreturn]] inline void fail(const std::string& layer, const std::string& what) {
  throw std::invalid_argument(layer + ": " + what);
}

inline void check_loop(const std::string& layer, uint64_t iterations, const std::string& what) {
  // llvmpipe silently ends invocations past 65,535 loop iterations (s4d_nn.h).
  if (iterations > S4D_NN_MAX_LOOP)
    fail(layer, what + " needs " + std::to_string(iterations) + " loop iterations per invocation, over the " +
                    std::to_string(S4D_NN_MAX_LOOP) + " the kernels allow");
}

}  // namespace s4d::nn::detail
