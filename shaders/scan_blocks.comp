// Exclusive prefix sum, step 1: each workgroup scans its 4 * local_size_x elements in
// place and writes the block total to sums[]. The host scans sums[] the same way
// (recursively) and scan_add.comp adds each block's offset. CPU reference:
// std::exclusive_scan in tests/host/test_scan.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/scan_abi.h"

layout(local_size_x_id = 0) in;

layout(std430, binding = SCAN_BIND_DATA) buffer Data { uint data[]; };
layout(std430, binding = SCAN_BIND_SUMS) writeonly buffer Sums { uint sums[]; };
layout(push_constant) uniform Push { ScanPush pc; };

shared uint partial[gl_WorkGroupSize.x];

void main() {
  uint block = gl_WorkGroupID.x + gl_WorkGroupID.y * pc.row_groups;
  uint lid = gl_LocalInvocationID.x;
  uint base = (block * gl_WorkGroupSize.x + lid) * SCAN_ITEMS_PER_THREAD;
  uint items[SCAN_ITEMS_PER_THREAD];
  uint sum = 0u;
  for (uint e = 0u; e < SCAN_ITEMS_PER_THREAD; ++e) {
    uint idx = base + e;
    uint x = idx < pc.count ? data[idx] : 0u;
    items[e] = sum;
    sum += x;
  }
  partial[lid] = sum;
  barrier();
  // Hillis-Steele inclusive scan of the per-thread sums.
  for (uint off = 1u; off < gl_WorkGroupSize.x; off <<= 1) {
    uint add = lid >= off ? partial[lid - off] : 0u;
    barrier();
    partial[lid] += add;
    barrier();
  }
  uint before = partial[lid] - sum;
  for (uint e = 0u; e < SCAN_ITEMS_PER_THREAD; ++e) {
    uint idx = base + e;
    if (idx < pc.count) data[idx] = before + items[e];
  }
  if (lid == gl_WorkGroupSize.x - 1u) sums[block] = partial[lid];
}
