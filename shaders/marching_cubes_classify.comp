// Marching cubes, pass 1: per grid point, which owned edges cross the surface and the
// case of its cube; writes the vertex and triangle counts that the scans turn into
// offsets. CPU reference: core/mc/marching_cubes_ref.cpp (classify_point).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/marching_cubes_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = MC_BIND_FIELD) readonly buffer Field { float field[]; };
layout(std430, binding = MC_BIND_INFO) writeonly buffer Info { uint info[]; };
layout(std430, binding = MC_BIND_VOFF) writeonly buffer VOff { uint vcount[]; };
layout(std430, binding = MC_BIND_TOFF) writeonly buffer TOff { uint tcount[]; };
layout(std140, binding = MC_BIND_TABLE) uniform Table { uvec4 cases[MC_TABLE_CASES]; };
layout(push_constant) uniform Push { McPush pc; };

uint inside(uint i, uint j, uint k) {
  return field[i + pc.nx * (j + pc.ny * k)] >= 0.0 ? 1u : 0u;
}

void main() {
  uint p = linear_invocation(pc.row);
  if (p >= pc.count) return;
  uint i = p % pc.nx, j = (p / pc.nx) % pc.ny, k = p / (pc.nx * pc.ny);
  uint s = inside(i, j, k);
  uint mask = 0u;
  if (i + 1u < pc.nx) mask |= (s ^ inside(i + 1u, j, k));
  if (j + 1u < pc.ny) mask |= (s ^ inside(i, j + 1u, k)) << 1;
  if (k + 1u < pc.nz) mask |= (s ^ inside(i, j, k + 1u)) << 2;
  uint cube = 0u;
  if (i + 1u < pc.nx && j + 1u < pc.ny && k + 1u < pc.nz) {
    cube = s | inside(i + 1u, j, k) << 1 | inside(i + 1u, j + 1u, k) << 2 | inside(i, j + 1u, k) << 3 |
           inside(i, j, k + 1u) << 4 | inside(i + 1u, j, k + 1u) << 5 | inside(i + 1u, j + 1u, k + 1u) << 6 |
           inside(i, j + 1u, k + 1u) << 7;
  }
  info[p] = mask | (cube << 3);
  vcount[p] = uint(bitCount(mask));
  tcount[p] = cases[cube].w;
}
