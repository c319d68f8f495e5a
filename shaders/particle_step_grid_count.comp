// Neighbour grid, step 1 of the counting sort: each particle's cell, and its rank among
// the particles of that cell (an atomic count). CPU reference: build_particle_grid in
// core/particles/particle_step_ref.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/particle_step_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = PT_BIND_POS) readonly buffer Pos { vec4 pos[]; };
layout(std430, binding = PT_BIND_CELL) writeonly buffer Cell { uint cell_of[]; };
layout(std430, binding = PT_BIND_RANK) writeonly buffer Rank { uint rank[]; };
layout(std430, binding = PT_BIND_START) buffer Start { uint start[]; };
layout(push_constant) uniform Push { ParticlePush pc; };

void main() {
  uint i = linear_invocation(pc.row);
  if (i >= pc.count) return;
  ivec3 dims = ivec3(pc.gx, pc.gy, pc.gz);
  ivec3 c = clamp(ivec3(floor((pos[i].xyz - vec3(pc.grid_x, pc.grid_y, pc.grid_z)) * pc.grid_inv_cell)), ivec3(0),
                  dims - 1);
  uint cell = uint(c.x) + pc.gx * (uint(c.y) + pc.gy * uint(c.z));
  cell_of[i] = cell;
  rank[i] = atomicAdd(start[cell], 1u);
}
