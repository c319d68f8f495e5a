// Marching cubes, pass 2: per grid point, the crossing vertices of its owned edges (at
// its scanned vertex offset) and the triangles of its cube (at its scanned triangle
// offset). A triangle corner on an edge owned by a neighbour point gets that point's
// offset plus the rank of the edge among its crossing edges: gathers only, no atomics,
// so the output order is fixed and equals the CPU reference's.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/marching_cubes_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = MC_BIND_FIELD) readonly buffer Field { float field[]; };
layout(std430, binding = MC_BIND_INFO) readonly buffer Info { uint info[]; };
layout(std430, binding = MC_BIND_VOFF) readonly buffer VOff { uint voff[]; };
layout(std430, binding = MC_BIND_TOFF) readonly buffer TOff { uint toff[]; };
layout(std430, binding = MC_BIND_VERTS) writeonly buffer Verts { vec4 verts[]; };
layout(std430, binding = MC_BIND_TRIS) writeonly buffer Tris { uint tris[]; };
layout(std140, binding = MC_BIND_TABLE) uniform Table { uvec4 cases[MC_TABLE_CASES]; };
layout(push_constant) uniform Push { McPush pc; };

// Owner offset (x, y, z) and axis (w) of each cube edge; see core/mc/mc_table.h.
const uvec4 kEdgeOwner[12] = uvec4[12](
    uvec4(0, 0, 0, 0), uvec4(1, 0, 0, 1), uvec4(0, 1, 0, 0), uvec4(0, 0, 0, 1),
    uvec4(0, 0, 1, 0), uvec4(1, 0, 1, 1), uvec4(0, 1, 1, 0), uvec4(0, 0, 1, 1),
    uvec4(0, 0, 0, 2), uvec4(1, 0, 0, 2), uvec4(1, 1, 0, 2), uvec4(0, 1, 0, 2));

void main() {
  uint p = linear_invocation(pc.row);
  if (p >= pc.count) return;
  uint i = p % pc.nx, j = (p / pc.nx) % pc.ny, k = p / (pc.nx * pc.ny);
  uint v = info[p];
  uint at = voff[p];
  float f0 = field[p];
  uint step[3] = uint[3](1u, pc.nx, pc.nx * pc.ny);
  for (uint a = 0u; a < 3u; ++a) {
    if (((v >> a) & 1u) == 0u) continue;
    float f1 = field[p + step[a]];
    float t = clamp(f0 / (f0 - f1), pc.min_frac, 1.0 - pc.min_frac);
    vec4 pos = vec4(float(i), float(j), float(k), 0.0);
    pos[a] += t;
    verts[at++] = pos;
  }
  uvec4 cc = cases[v >> 3];
  uint t_at = toff[p];
  for (uint t = 0u; t < cc.w; ++t) {
    for (uint c = 0u; c < 3u; ++c) {
      uint slot = 3u * t + c;
      uint word = slot < 8u ? cc.x : (slot < 16u ? cc.y : cc.z);
      uint e = (word >> (4u * (slot & 7u))) & 15u;
      uvec4 eo = kEdgeOwner[e];
      uint q = (i + eo.x) + pc.nx * ((j + eo.y) + pc.ny * (k + eo.z));
      uint below = info[q] & ((1u << eo.w) - 1u);
      tris[3u * t_at + c] = voff[q] + uint(bitCount(below));
    }
    ++t_at;
  }
}
