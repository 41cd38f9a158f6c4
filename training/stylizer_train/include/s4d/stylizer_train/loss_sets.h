// The loss sets of train-stylizer's --losses (the ablation of HGST's loss, ALGORITHMS.md 4.5):
// which terms train the decoder and MCC module and at which VGG levels. A term that is off has
// weight 0: its value is still computed and logged, but it adds nothing to the total or gradients.
//   mccnet   MCCNet's own loss: content (relu4_1, relu5_1), mean/std style (relu1_1 .. relu5_1),
//            identity 1 and 2, noise; no TV, no self-similarity
//   content  mccnet with HGST's content levels (relu3_1, relu4_1, relu5_1)
//   full     HGST's loss as far as it exists: HGST's content and style levels, every term above
//            plus TV and the self-similarity "Iins" (CCPL is not implemented yet)
// The shared terms keep HGST's weights in every set, so the sets differ only in their terms.
#pragma once
#include <string>
#include <vector>

#include "s4d/nn/mcc_loss.h"

namespace s4d::stylizer_train {

struct LossSet {
  nn::MccLossLevels levels;
  nn::MccLossWeights weights;
};

// The names loss_set() accepts, in ablation order.
const std::vector<std::string>& loss_set_names();

// Throws std::invalid_argument("--losses: expected one of mccnet, content, full, got '<name>'").
LossSet loss_set(const std::string& name);

}  // namespace s4d::stylizer_train
