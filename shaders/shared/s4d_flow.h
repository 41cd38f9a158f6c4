// Shared layouts of the exact-flow kernels: where each Gaussian's mean lands on screen in one frame
// (flow_project) and its screen displacement between two frames as a per-Gaussian colour
// (flow_displace), which the rasterizer then blends into a flow image. CPU twin:
// training/ref/include/s4d/ref/flow_ref.h.
#ifndef S4D_FLOW_H
#define S4D_FLOW_H
#include "s4d_splat.h"

#define S4D_FLOW_WG 256

// Per-Gaussian screen lanes written by flow_project: [N * S4D_FLOW_SCREEN_STRIDE] floats.
#define S4D_FLOW_SCREEN_U 0      // u = fx x / z + cx, pixels (0 when not valid)
#define S4D_FLOW_SCREEN_V 1      // v = fy y / z + cy
#define S4D_FLOW_SCREEN_VALID 2  // 1 when the mean is in front of the near plane (z > S4D_NEAR_Z), else 0
#define S4D_FLOW_SCREEN_STRIDE 3

// Binding ids.
#define S4D_B_FLOWP_MEANS 0    // [N*3] f32 world means
#define S4D_B_FLOWP_SCREEN 1   // [N*3] f32 screen lanes, written
#define S4D_B_FLOWD_FROM 0     // [N*3] screen lanes in the frame the flow starts from
#define S4D_B_FLOWD_TO 1       // [N*3] screen lanes in the frame it goes to
#define S4D_B_FLOWD_COLORS 2   // [N*3] f32 (du, dv, 0) = to - from, 0 unless valid in both; written

S4D_NAMESPACE_BEGIN

// Push constants of flow_project.
struct FlowProjectParams {
  SplatCamera cam;
  uint n;  // Gaussians
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

// Push constants of flow_displace.
struct FlowDisplaceParams {
  uint n;  // Gaussians
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

S4D_NAMESPACE_END

#endif  // S4D_FLOW_H
