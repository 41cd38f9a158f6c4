// graphdeco's camera order: a stack of every training view, popped at random and refilled when
// empty, so each epoch sees every view once. Its state round-trips through text for checkpoints.
#pragma once
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace s4d::train {

class ViewSampler {
 public:
  ViewSampler(uint32_t views, uint64_t seed);
  uint32_t next();
  std::string save() const;
  // Throws std::runtime_error when `state` was not written by save() for the same view count.
  void load(const std::string& state);

 private:
  uint32_t views_;
  std::mt19937_64 rng_;
  std::vector<uint32_t> stack_;
};

}  // namespace s4d::train
