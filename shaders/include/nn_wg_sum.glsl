// Sum of one float over a workgroup of S4D_NN_STATS_WG invocations (S4D_NN_WG is the same size), in
// shared memory, so no subgroup size is assumed. Every invocation of the workgroup must call it.
shared float wg_partial[S4D_NN_STATS_WG];

float wg_sum(float v) {
  uint l = gl_LocalInvocationIndex;
  wg_partial[l] = v;
  barrier();
  for (uint s = S4D_NN_STATS_WG / 2; s > 0; s >>= 1) {
    if (l < s) wg_partial[l] += wg_partial[l + s];
    barrier();
  }
  float total = wg_partial[0];
  barrier();  // wg_partial[] is reused by the next call
  return total;
}
