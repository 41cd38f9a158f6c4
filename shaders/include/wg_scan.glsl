// Workgroup-wide exclusive prefix sums that assume no particular subgroup size or layout.
//
// Invocations are ordered by (gl_SubgroupID, gl_SubgroupInvocationID); wg_rank() gives each
// invocation its position in that order, and kernels index their data by that rank rather than by
// gl_LocalInvocationIndex, so results stay correct where subgroups are partial or the driver maps
// local indices to subgroups differently. The includer defines WG_SIZE. Each call contains
// barriers and must be reached by the whole workgroup.

shared uvec4 wg_scan_totals[2][WG_SIZE];
shared uvec4 wg_scan_sum[2];

// Exclusive prefix of (a, b) over the workgroup, eight independent u32 lanes at once (two uvec4
// so packed counters need one pass); the workgroup sums go to total_a, total_b.
void wg_exclusive_add8(inout uvec4 a, inout uvec4 b, out uvec4 total_a, out uvec4 total_b) {
  uvec4 incl_a = subgroupInclusiveAdd(a);
  uvec4 incl_b = subgroupInclusiveAdd(b);
  uvec4 sum_a = subgroupAdd(a);
  uvec4 sum_b = subgroupAdd(b);
  if (subgroupElect()) {
    wg_scan_totals[0][gl_SubgroupID] = sum_a;
    wg_scan_totals[1][gl_SubgroupID] = sum_b;
  }
  barrier();
  // Subgroup 0 scans the per-subgroup sums in chunks of its active size, carrying the running sum.
  if (gl_SubgroupID == 0) {
    // Lanes are numbered by active rank, not gl_SubgroupInvocationID, in case subgroup 0 is partial.
    uint lane = subgroupExclusiveAdd(1u);
    uint lanes = subgroupAdd(1u);
    uvec4 carry_a = uvec4(0), carry_b = uvec4(0);
    for (uint base = 0; base < gl_NumSubgroups; base += lanes) {
      uint i = base + lane;
      bool live = i < gl_NumSubgroups;
      uvec4 ta = live ? wg_scan_totals[0][i] : uvec4(0);
      uvec4 tb = live ? wg_scan_totals[1][i] : uvec4(0);
      uvec4 ia = subgroupInclusiveAdd(ta);
      uvec4 ib = subgroupInclusiveAdd(tb);
      if (live) {
        wg_scan_totals[0][i] = carry_a + ia - ta;
        wg_scan_totals[1][i] = carry_b + ib - tb;
      }
      carry_a += subgroupAdd(ta);
      carry_b += subgroupAdd(tb);
    }
    if (subgroupElect()) {
      wg_scan_sum[0] = carry_a;
      wg_scan_sum[1] = carry_b;
    }
  }
  barrier();
  uvec4 prefix_a = wg_scan_totals[0][gl_SubgroupID] + incl_a - a;
  uvec4 prefix_b = wg_scan_totals[1][gl_SubgroupID] + incl_b - b;
  total_a = wg_scan_sum[0];
  total_b = wg_scan_sum[1];
  barrier();  // the shared state is reused by the next call
  a = prefix_a;
  b = prefix_b;
}

uint wg_exclusive_add(uint v, out uint total) {
  uvec4 a = uvec4(v, 0, 0, 0), b = uvec4(0), ta, tb;
  wg_exclusive_add8(a, b, ta, tb);
  total = ta.x;
  return a.x;
}

// Position of this invocation in the (subgroup, lane) order, 0 .. WG_SIZE-1.
uint wg_rank() {
  uint total;
  return wg_exclusive_add(1u, total);
}
