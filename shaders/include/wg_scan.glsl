// Workgroup-wide exclusive prefix sums that assume no particular subgroup size or layout.
//
// Invocations are ordered by (gl_SubgroupID, gl_SubgroupInvocationID); wg_rank() gives each
// invocation its position in that order, and kernels index their data by that rank rather than by
// gl_LocalInvocationIndex, so results stay correct where subgroups are partial or the driver maps
// local indices to subgroups differently. The includer defines WG_SIZE. Each call contains
// barriers and must be reached by the whole workgroup.

shared uvec4 wg_scan_totals[WG_SIZE];
shared uvec4 wg_scan_sum;

// Exclusive prefix of v over the workgroup, four independent lanes at once; the workgroup sum
// goes to `total`.
uvec4 wg_exclusive_add4(uvec4 v, out uvec4 total) {
  uvec4 incl = subgroupInclusiveAdd(v);
  uvec4 sg_sum = subgroupAdd(v);
  if (subgroupElect()) wg_scan_totals[gl_SubgroupID] = sg_sum;
  barrier();
  // Subgroup 0 scans the per-subgroup sums in chunks of its own size, carrying the running sum.
  if (gl_SubgroupID == 0) {
    uvec4 carry = uvec4(0);
    for (uint base = 0; base < gl_NumSubgroups; base += gl_SubgroupSize) {
      uint i = base + gl_SubgroupInvocationID;
      uvec4 t = i < gl_NumSubgroups ? wg_scan_totals[i] : uvec4(0);
      uvec4 ti = subgroupInclusiveAdd(t);
      if (i < gl_NumSubgroups) wg_scan_totals[i] = carry + ti - t;
      carry += subgroupAdd(t);
    }
    if (subgroupElect()) wg_scan_sum = carry;
  }
  barrier();
  uvec4 prefix = wg_scan_totals[gl_SubgroupID] + incl - v;
  total = wg_scan_sum;
  barrier();  // the shared state is reused by the next call
  return prefix;
}

uint wg_exclusive_add(uint v, out uint total) {
  uvec4 total4;
  uint prefix = wg_exclusive_add4(uvec4(v, 0, 0, 0), total4).x;
  total = total4.x;
  return prefix;
}

// Position of this invocation in the (subgroup, lane) order, 0 .. WG_SIZE-1.
uint wg_rank() {
  uint total;
  return wg_exclusive_add(1u, total);
}
