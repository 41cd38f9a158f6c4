// Shared layouts of the optimizer kernels: Adam (PyTorch semantics, bias-corrected) with
// per-parameter-group hyperparameters in a small device buffer the host rewrites each step.
#ifndef S4D_OPTIM_H
#define S4D_OPTIM_H
#include "s4d_common.h"

#define S4D_ADAM_WG 256
// Adam sees gradients clamped to +-S4D_ADAM_MAX_GRAD (NaN passes through, for the trainer's
// rollback): the square of a larger one overflows float to inf, which would stop the parameter for
// good (m / sqrt(inf) = 0) and put inf in its second moment and the next checkpoint. 1e18 squared
// stays finite, and a clamped first step moves the parameter by lr like any other.
#define S4D_ADAM_MAX_GRAD 1e18
#define S4D_B_ADAM_GROUPS 0  // [groups] AdamGroup
#define S4D_B_ADAM_PARAMS 1  // [n] float, updated in place
#define S4D_B_ADAM_GRADS 2   // [n] float
#define S4D_B_ADAM_M 3       // [n] float first moment
#define S4D_B_ADAM_V 4       // [n] float second moment

#define S4D_ADD_WG 256
#define S4D_B_ADD_DST 0  // [n] float, += src
#define S4D_B_ADD_SRC 1  // [n] float

#define S4D_MASK_WG 256
#define S4D_B_MASK_VALUES 0  // [rows * row] float, zeroed where the row's mask is 0
#define S4D_B_MASK_ROWS 1    // [rows] u32, non-zero keeps the row

S4D_NAMESPACE_BEGIN

// One parameter group's hyperparameters for the current step.
struct AdamGroup {
  float lr;
  float beta1;
  float beta2;
  float eps;
  float inv_bias1;       // 1 / (1 - beta1^t)
  float inv_sqrt_bias2;  // 1 / sqrt(1 - beta2^t)
  uint step;             // t, 1-based
  uint _pad0;
};

// Push constants of adam_step. A tensor of rows (one per Gaussian) may split each row between two
// groups: element i uses `group` when i % row < head and `tail_group` otherwise (3DGS trains the SH
// DC term and the higher coefficients, stored in one row, at different learning rates).
struct AdamParams {
  uint n;           // elements of this tensor
  uint group;       // index into the group buffer
  uint tail_group;  // group of each row's elements from `head` on
  uint row;         // row length (1 with head 1: one group for all)
  uint head;
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

// Push constants of grad_add (the gradients of a batch's views summed into one).
struct AddParams {
  uint n;
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

// Push constants of grad_mask (gradients of the Gaussians a region leaves out set to zero).
struct MaskParams {
  uint n;    // floats: rows * row
  uint row;  // floats per row
  uint _pad0;
  uint _pad1;
};

S4D_NAMESPACE_END

#endif  // S4D_OPTIM_H
