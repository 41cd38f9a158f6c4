// Shared layouts and constants of the image losses (ALGORITHMS.md 2.3): L1 and SSIM with an 11x11
// Gaussian window (sigma 1.5), zero padding 5, C1 = 0.01^2, C2 = 0.03^2, the map averaged.
// Images are float [H*W*C] row-major, channels interleaved; SSIM is per channel.
#ifndef S4D_LOSS_H
#define S4D_LOSS_H
#include "s4d_common.h"

#define S4D_SSIM_RADIUS 5
#define S4D_SSIM_C1 0.0001
#define S4D_SSIM_C2 0.0009
// Normalised 1-D Gaussian taps w[|k|], k = -5..5, sigma 1.5 (the 2-D window is their outer product).
#define S4D_SSIM_W0 0.26601172486179436
#define S4D_SSIM_W1 0.21300553771125369
#define S4D_SSIM_W2 0.10936068950970002
#define S4D_SSIM_W3 0.036000772128430829
#define S4D_SSIM_W4 0.007598758135239185
#define S4D_SSIM_W5 0.0010283800844791101

#define S4D_LOSS_WG 256
#define S4D_SSIM_STATS 5   // filtered x, y, x^2, y^2, xy
#define S4D_SSIM_DMAPS 3   // dS/d mu_x, dS/d E[x^2], dS/d E[xy], pre-scaled by -ssim_weight / count

// Binding ids: ssim_hpass (forward statistics and backward maps share the kernel with a mode flag).
#define S4D_B_SSIM_H_IN_A 0      // fwd: image x [n]; bwd: dmaps [3n]
#define S4D_B_SSIM_H_IN_B 1      // fwd: target y [n]; bwd: unused (bind anything)
#define S4D_B_SSIM_H_OUT 2       // fwd: [5n] horizontally filtered stats; bwd: [3n] filtered dmaps
#define S4D_B_SSIM_V_IMAGE 0     // ssim_vpass: image x [n]
#define S4D_B_SSIM_V_TARGET 1    // target y [n]
#define S4D_B_SSIM_V_STATS_H 2   // [5n]
#define S4D_B_SSIM_V_DMAPS 3     // out [3n]
#define S4D_B_SSIM_V_PARTIALS 4  // out [2 * groups]: per workgroup (sum of SSIM map, sum |x - y|)
#define S4D_B_LOSS_GRAD_IMAGE 0  // loss_grad: image x [n]
#define S4D_B_LOSS_GRAD_TARGET 1 // target y [n]
#define S4D_B_LOSS_GRAD_DMAPS_H 2 // [3n] horizontally filtered dmaps
#define S4D_B_LOSS_GRAD_OUT 3    // out dL/dx [n]

// Binding ids: tv_grad (squared total variation of an image, value partials and gradient).
#define S4D_B_TV_IMAGE 0         // image x [n]
#define S4D_B_TV_GRAD 1          // dL/dx [n]: the TV gradient is added to what is there
#define S4D_B_TV_PARTIALS 2      // out [groups]: per workgroup sum of squared right and down differences

S4D_NAMESPACE_BEGIN

// Push constants of ssim_hpass, ssim_vpass and loss_grad.
struct LossParams {
  uint width;
  uint height;
  uint channels;
  uint n;              // width * height * channels
  float ssim_weight;   // lambda: loss = (1 - lambda) L1 + lambda (1 - SSIM)
  float inv_count;     // 1 / n
  uint mode;           // ssim_hpass: 0 = forward statistics, 1 = backward maps
  uint _pad0;
};

// Push constants of tv_grad: L = weight * inv_pairs * sum over neighbour pairs (x_a - x_b)^2, pairs
// being horizontal and vertical neighbours within one channel.
struct TvParams {
  uint width;
  uint height;
  uint channels;
  uint n;              // width * height * channels
  float weight;
  float inv_pairs;     // 1 / (channels * ((width - 1) * height + width * (height - 1)))
  uint _pad0;
  uint _pad1;
};

S4D_NAMESPACE_END

#endif  // S4D_LOSS_H
