#include "s4d/stylizer_train/loss_sets.h"

#include <stdexcept>

namespace s4d::stylizer_train {

const std::vector<std::string>& loss_set_names() {
  static const std::vector<std::string> names = {"mccnet", "ccpl", "content", "lcl", "full"};
  return names;
}

LossSet loss_set(const std::string& name) {
  if (name == "full") return {nn::MccLossLevels::hgst(), {}, nn::CcplConfig::hgst()};
  LossSet set{nn::MccLossLevels::mccnet(), {}, nn::CcplConfig::hgst()};
  set.weights.tv = 0.0f;
  set.weights.selfsim = 0.0f;
  set.weights.ccpl = 0.0f;
  if (name == "mccnet") return set;
  if (name == "ccpl") {
    set.ccpl = nn::CcplConfig::original();
    set.weights.ccpl = 5.0f;  // CCPL's train.py --ccp_weight
    return set;
  }
  set.levels.content = nn::MccLossLevels::hgst().content;
  if (name == "content") return set;
  if (name == "lcl") {
    set.weights.ccpl = nn::MccLossWeights{}.ccpl;  // HGST's 4
    return set;
  }
  std::string expected;
  for (const std::string& n : loss_set_names()) expected += (expected.empty() ? "" : ", ") + n;
  throw std::invalid_argument("--losses: expected one of " + expected + ", got '" + name + "'");
}

}  // namespace s4d::stylizer_train
