// Exclusive prefix sum, step 2: adds each block's scanned offset to its elements.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/scan_abi.h"

layout(local_size_x_id = 0) in;

layout(std430, binding = SCAN_BIND_DATA) buffer Data { uint data[]; };
layout(std430, binding = SCAN_BIND_SUMS) readonly buffer Sums { uint sums[]; };
layout(push_constant) uniform Push { ScanPush pc; };

void main() {
  uint block = gl_WorkGroupID.x + gl_WorkGroupID.y * pc.row_groups;
  uint base = (block * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * SCAN_ITEMS_PER_THREAD;
  uint offset = sums[block];
  for (uint e = 0u; e < SCAN_ITEMS_PER_THREAD; ++e) {
    uint idx = base + e;
    if (idx < pc.count) data[idx] += offset;
  }
}
