// Neighbour grid, step 3 of the counting sort (step 2 is the exclusive scan of the
// counts, scan_*.comp): each particle to its slot in its cell's run.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/particle_step_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = PT_BIND_CELL) readonly buffer Cell { uint cell_of[]; };
layout(std430, binding = PT_BIND_RANK) readonly buffer Rank { uint rank[]; };
layout(std430, binding = PT_BIND_START) readonly buffer Start { uint start[]; };
layout(std430, binding = PT_BIND_ORDER) writeonly buffer Order { uint order[]; };
layout(push_constant) uniform Push { ParticlePush pc; };

void main() {
  uint i = linear_invocation(pc.row);
  if (i >= pc.count) return;
  order[start[cell_of[i]] + rank[i]] = i;
}
