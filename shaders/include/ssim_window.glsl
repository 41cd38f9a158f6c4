// The SSIM window's 1-D taps (s4d_loss.h), indexed by offset -5..5.
#ifndef SSIM_WINDOW_GLSL
#define SSIM_WINDOW_GLSL
const float SSIM_TAPS[2 * S4D_SSIM_RADIUS + 1] =
    float[](S4D_SSIM_W5, S4D_SSIM_W4, S4D_SSIM_W3, S4D_SSIM_W2, S4D_SSIM_W1, S4D_SSIM_W0, S4D_SSIM_W1,
            S4D_SSIM_W2, S4D_SSIM_W3, S4D_SSIM_W4, S4D_SSIM_W5);

// Element index -> (x, y, channel) of an interleaved [H, W, C] image.
uvec3 loss_coords(uint e, uint width, uint channels) {
  uint c = e % channels, pixel = e / channels;
  return uvec3(pixel % width, pixel / width, c);
}
#endif  // SSIM_WINDOW_GLSL
