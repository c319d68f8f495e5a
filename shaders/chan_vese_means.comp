// Chan-Vese, pass 1 of an iteration: one workgroup per slice reduces the exact integer
// sums of u over phi >= 0 and over the whole slice (64-bit, as two words with carry) and
// the inside count, and writes the region means c1 (inside) and c2 (outside).
// CPU reference: core/segment/chan_vese_ref.cpp (slice_means).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/chan_vese_abi.h"

layout(local_size_x_id = 0) in;

layout(std430, binding = CV_BIND_U) readonly buffer U { float u[]; };
layout(std430, binding = CV_BIND_PHI_IN) readonly buffer Phi { float phi[]; };
layout(std430, binding = CV_BIND_MEANS) writeonly buffer Means { vec4 means[]; };
layout(push_constant) uniform Push { CvPush pc; };

shared uvec2 s_in[gl_WorkGroupSize.x];
shared uvec2 s_all[gl_WorkGroupSize.x];
shared uint s_count[gl_WorkGroupSize.x];

uvec2 add64(uvec2 a, uvec2 b) {
  uint carry;
  uint lo = uaddCarry(a.x, b.x, carry);
  return uvec2(lo, a.y + b.y + carry);
}

float to_float(uvec2 v) { return float(v.y) * 4294967296.0 + float(v.x); }

void main() {
  uint slice = gl_WorkGroupID.x;
  uint lid = gl_LocalInvocationID.x;
  uint n = pc.nx * pc.ny;
  uint base = slice * n;
  uvec2 sin_ = uvec2(0u), sall = uvec2(0u);
  uint cin = 0u;
  for (uint p = lid; p < n; p += gl_WorkGroupSize.x) {
    uint v = uint(u[base + p]);
    uint inside = phi[base + p] >= 0.0 ? 1u : 0u;
    sin_ = add64(sin_, uvec2(v * inside, 0u));
    sall = add64(sall, uvec2(v, 0u));
    cin += inside;
  }
  s_in[lid] = sin_;
  s_all[lid] = sall;
  s_count[lid] = cin;
  barrier();
  // Pairwise tree; works for any workgroup size.
  for (uint off = 1u; off < gl_WorkGroupSize.x; off <<= 1) {
    if ((lid & (2u * off - 1u)) == 0u && lid + off < gl_WorkGroupSize.x) {
      s_in[lid] = add64(s_in[lid], s_in[lid + off]);
      s_all[lid] = add64(s_all[lid], s_all[lid + off]);
      s_count[lid] += s_count[lid + off];
    }
    barrier();
  }
  if (lid == 0u) {
    uint count_in = s_count[0];
    uint count_out = n - count_in;
    uvec2 sum_in = s_in[0];
    // sum_out = sum_all - sum_in, with borrow.
    uvec2 sum_all = s_all[0];
    uint borrow;
    uint lo = usubBorrow(sum_all.x, sum_in.x, borrow);
    uvec2 sum_out = uvec2(lo, sum_all.y - sum_in.y - borrow);
    float c1 = count_in > 0u ? to_float(sum_in) / float(count_in) : CV_EMPTY_C1;
    float c2 = count_out > 0u ? to_float(sum_out) / float(count_out) : CV_EMPTY_C2;
    means[slice] = vec4(c1, c2, float(count_in), 0.0);
  }
}
