// The loss sets of train-stylizer's --losses (the ablation of HGST's loss, ALGORITHMS.md 4.5):
// which terms train the decoder and MCC module and at which VGG levels. A term that is off has
// weight 0: its value is still computed and logged, but it adds nothing to the total or gradients.
//   mccnet   MCCNet's own loss: content (relu4_1, relu5_1), mean/std style (relu1_1 .. relu5_1),
//            identity 1 and 2, noise; no TV, no self-similarity, no CCPL
//   ccpl     mccnet + the original CCPL (Wu et al. 2022, its train.py: relu2_1 .. relu4_1, 8 anchors,
//            no jitter, weight 5, the projection heads trained with the decoder and MCC)
//   content  mccnet with HGST's content levels (relu3_1, relu4_1, relu5_1)
//   lcl      content + HGST's CCPL, "LCL" (relu3_1, relu4_1, 16 anchors, jittered neighbours,
//            weight 4, the heads left at their seeded random init as HGST's optimiser leaves them)
//   full     HGST's loss: HGST's content and style levels, every term above plus TV, the
//            self-similarity "Iins" and LCL
// The shared terms keep HGST's weights in every set, so the sets differ only in their terms. Sets
// without a CCPL term log HGST's variant at weight 0.
#pragma once
#include <string>
#include <vector>

#include "s4d/nn/ccpl.h"
#include "s4d/nn/mcc_loss.h"

namespace s4d::stylizer_train {

struct LossSet {
  nn::MccLossLevels levels;
  nn::MccLossWeights weights;
  nn::CcplConfig ccpl;  // the CCPL variant (logged at weight 0 where the set has none)
};

// The names loss_set() accepts, in ablation order.
const std::vector<std::string>& loss_set_names();

// Throws std::invalid_argument("--losses: expected one of mccnet, ccpl, content, lcl, full, got '<name>'").
LossSet loss_set(const std::string& name);

}  // namespace s4d::stylizer_train
