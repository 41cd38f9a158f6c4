// The backward passes of the network layers that the MCCNet/HGST decoder, MCC module and VGG
// encoder use (kernels in shaders/nn/*_bwd.comp, nn_conv_wgrad, nn_channel_dots, nn_mse; layouts in
// shaders/shared/s4d_nn_grad.h; twins in training/ref/.../nn_grad_ref.h). As in layers.h each call
// records its dispatches followed by a barrier and throws std::invalid_argument naming the layer
// and the shapes before recording anything. "dy" is dL/d(output), "dx" dL/d(input).
#pragma once
#include <cstdint>
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

// dL/dW and dL/db of one ConvWeights, the same shapes.
struct ConvGrads {
  engine::Buffer weight;  // [cout, cin, k, k]
  engine::Buffer bias;    // [cout]
};

// Gradient buffers for `w`, zero-filled by the recorded fill.
ConvGrads zero_conv_grads(engine::Recorder& rec, const ConvWeights& w);
// A [c, h, w] tensor of zeros (an accumulation target).
Tensor zero_tensor(engine::Recorder& rec, const std::string& name, uint32_t c, uint32_t h, uint32_t w);

// dx of conv3x3 (reflection padding, k = 3) or conv1x1 (k = 1) without its ReLU (see relu_backward).
Tensor conv_backward_input(engine::Recorder& rec, const Tensor& dy, const ConvWeights& w);
// dx += the same (residual connections, a feature that feeds two layers).
void conv_backward_input_accumulate(engine::Recorder& rec, const Tensor& dy, const ConvWeights& w, Tensor& dx);
// grads (+)= dL/dW, dL/db of conv3x3 (reflection) or conv1x1 given its input x and dy.
void conv_backward_weights(engine::Recorder& rec, const Tensor& x, const Tensor& dy, const ConvWeights& w,
                           ConvGrads& grads, bool accumulate);
// dy = 0 where the ReLU's output y is not positive, in place.
void relu_backward(engine::Recorder& rec, Tensor& dy, const Tensor& y);
// dx of upsample2: [c, h / 2, w / 2] from dy [c, h, w] (h, w even).
Tensor upsample2_backward(engine::Recorder& rec, const Tensor& dy);
// dx of maxpool2 (ceil mode) given its input x and dy [c, ceil(h/2), ceil(w/2)].
Tensor maxpool2_backward(engine::Recorder& rec, const Tensor& x, const Tensor& dy);
// dx of avgpool3 given dy [c, h - 2, w - 2].
Tensor avgpool3_backward(engine::Recorder& rec, const Tensor& dy);
// Per channel [maxima..., index of each maximum's first occurrence (as floats)...] ([2, c]).
engine::Buffer channel_max(engine::Recorder& rec, const Tensor& x);
// HGST's self-similarity of v = avgpool3(relu5_1) >= 0 (s4d_nn_grad.h): grad += weight / C times
// the gradient of sum_c Iins_c; returns a one-float buffer holding sum_c Iins_c.
engine::Buffer selfsim(engine::Recorder& rec, const Tensor& v, const Tensor& grad, float weight);
// Per channel [sum_p a, sum_p a b] ([2, c]).
engine::Buffer channel_dots(engine::Recorder& rec, const Tensor& a, const Tensor& b);
// dx += dL/dx of mean_std(x) (its output `stats`) given dstats = [dmu..., dsigma...].
void mean_std_backward(engine::Recorder& rec, const Tensor& x, const engine::Buffer& stats, const engine::Buffer& dstats,
                       Tensor& dx);
// dx += dL/dx of y = normalise(x, stats) given y and dy.
void normalise_backward(engine::Recorder& rec, const Tensor& x, const engine::Buffer& stats, const Tensor& y,
                        const Tensor& dy, Tensor& dx);
// dx of squares_over_sum(x) given da [c, 1, 1].
Tensor squares_over_sum_backward(engine::Recorder& rec, const Tensor& x, const Tensor& da);
// A squared-error term over `count` floats of buffers a and b: grad += scale (a - b); returns the
// per-workgroup sums of (a - b)^2 (add them with squared_error_value after the run).
engine::Buffer squared_error(engine::Recorder& rec, const engine::Buffer& a, const engine::Buffer& b,
                             const engine::Buffer& grad, size_t count, float scale);
// MCCNet's TV term sum |x[.., y, x] - x[.., y, x + 1]| + |x[.., y, x] - x[.., y + 1, x]| of x:
// grad += weight dTV/dx; returns partial sums of the TV (add them with squared_error_value).
engine::Buffer tv_l1(engine::Recorder& rec, const Tensor& x, const Tensor& grad, float weight);
// The sum of squared_error's (or tv_l1's) partials, after the work that wrote them ran.
double squared_error_value(engine::Context& ctx, const engine::Buffer& partials);

}  // namespace s4d::nn
