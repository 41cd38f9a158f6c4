#include "s4d/train/view_sampler.h"

#include <sstream>
#include <stdexcept>

namespace s4d::train {

ViewSampler::ViewSampler(uint32_t views, uint64_t seed) : views_(views), rng_(seed) {
  if (views == 0) throw std::invalid_argument("no training views to sample from");
}

uint32_t ViewSampler::next() {
  if (stack_.empty())
    for (uint32_t v = 0; v < views_; ++v) stack_.push_back(v);
  const size_t k = std::uniform_int_distribution<size_t>(0, stack_.size() - 1)(rng_);
  const uint32_t view = stack_[k];
  stack_[k] = stack_.back();
  stack_.pop_back();
  return view;
}

std::string ViewSampler::save() const {
  std::ostringstream out;
  out << views_ << ' ' << stack_.size();
  for (uint32_t v : stack_) out << ' ' << v;
  out << ' ' << rng_;
  return out.str();
}

void ViewSampler::load(const std::string& state) {
  std::istringstream in(state);
  uint32_t views = 0;
  size_t n = 0;
  in >> views >> n;
  if (!in || views != views_ || n > views)
    throw std::runtime_error("checkpoint view sampler: saved for " + std::to_string(views) + " views, this run has " +
                             std::to_string(views_));
  std::vector<uint32_t> stack(n);
  for (uint32_t& v : stack) in >> v;
  std::mt19937_64 rng;
  in >> rng;
  if (!in) throw std::runtime_error("checkpoint view sampler: corrupt state");
  stack_ = std::move(stack);
  rng_ = rng;
}

}  // namespace s4d::train
