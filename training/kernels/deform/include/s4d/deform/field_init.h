// Initial parameters of the deformation field (ALGORITHMS.md 3.1): spatial planes U(0.1, 0.5), time
// planes 1; Linear weights xavier-uniform (gain 1), biases U(-1/sqrt(fan_in), 1/sqrt(fan_in)) (PyTorch's
// default, which 4DGaussians keeps by a bug). Deterministic for a seed on every platform (no
// std:: distributions, whose output differs between standard libraries).
#pragma once
#include <cstdint>
#include <vector>

#include "s4d_deform.h"

namespace s4d::deform {

std::vector<float> initial_planes(const gpu::DeformShape& shape, uint32_t seed);
std::vector<float> initial_mlp(const gpu::DeformShape& shape, uint32_t seed);

}  // namespace s4d::deform
