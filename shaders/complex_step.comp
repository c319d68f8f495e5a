// One step of the multi-material complex's sampling, one invocation per particle, from
// the state before the step (pc.step: onto the interface, the junction candidate, the
// junction relaxation, the interface relaxation). CPU reference: complex_step in
// core/multi/complex_step_ref.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/complex_abi.h"
#include "shared/mpu_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = CX_BIND_LEAVES) readonly buffer Leaves { vec4 leaves[]; };
layout(std430, binding = CX_BIND_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = CX_BIND_LEAF_IDS) readonly buffer LeafIds { uint leaf_ids[]; };
layout(std430, binding = CX_BIND_FITS) readonly buffer Fits { CxFit fits[]; };
layout(std430, binding = CX_BIND_REGIONS) readonly buffer Regions { CxRegion regions_[]; };
layout(std430, binding = CX_BIND_SUPPORT) readonly buffer Support { uint support[]; };
layout(std430, binding = CX_BIND_IN) readonly buffer In { vec4 in_pos[]; };
layout(std430, binding = CX_BIND_IN_REGIONS) readonly buffer InRegions { ivec4 in_regions[]; };
layout(std430, binding = CX_BIND_IN_KIND) readonly buffer InKind { uint in_kind[]; };
layout(std430, binding = CX_BIND_FIRST) readonly buffer First { uint first[]; };
layout(std430, binding = CX_BIND_NEIGHBOURS) readonly buffer Neighbours { uint neighbours[]; };
layout(std430, binding = CX_BIND_OUT) writeonly buffer Out { vec4 out_pos[]; };
layout(std430, binding = CX_BIND_OUT_REGIONS) writeonly buffer OutRegions { ivec4 out_regions[]; };
layout(std430, binding = CX_BIND_OUT_STATE) writeonly buffer OutState { uint out_state[]; };
layout(push_constant) uniform Push { ComplexPush pc; };

#define MPU_GRID_FROM_TABLE
#include "lib/mpu_eval.glsl"
#include "lib/material_field.glsl"

// As core/multi/complex_step_ref.h.
const float kReach = 2.0;          // kComplexReach
const float kRelaxReach = 1.3;     // kRelaxReach
const float kRelaxStepCap = 0.25;  // kRelaxStepCap
const float kJunctionBand = 1.0;
const float kCornerBand = 0.15;

uvec3 sort3(uvec3 v) {
  if (v.x > v.y) v.xy = v.yx;
  if (v.y > v.z) v.yz = v.zy;
  if (v.x > v.y) v.xy = v.yx;
  return v;
}

uvec4 sort4(uvec4 v) {
  if (v.x > v.y) v.xy = v.yx;
  if (v.z > v.w) v.zw = v.wz;
  if (v.x > v.z) v.xz = v.zx;
  if (v.y > v.w) v.yw = v.wy;
  if (v.y > v.z) v.yz = v.zy;
  return v;
}

struct Result {
  bool ok;
  vec3 p;
  ivec4 regions;
  uint kind;
};

// The junction (or corner) point nearest an interface particle whose third region is
// within the band: onto the curve of the three, then, where a fourth is within the corner
// band, onto the point of the four (a pass each through one projection).
Result junction_candidate_step(vec3 p, float s) {
  Result r;
  r.ok = false;
  if (pc.regions < 3u) return r;
  Ranked k = ranked(p);
  if (k.f[2] - k.f[0] > kJunctionBand * s) return r;
  uvec3 abc = sort3(uvec3(k.r[0], k.r[1], k.r[2]));
  uvec4 regs = uvec4(abc, 0u);
  uint n = 3u;
  vec3 q = p;
  for (int pass = 0; pass < 2; ++pass) {
    if (!project_equal(q, regs, n, kReach * s)) return r;
    if (pass == 1) {
      r.p = q;
      r.kind = CX_KIND_CORNER;
      r.regions = ivec4(regs);
      return r;
    }
    Ranked at = ranked(q);
    if (sort3(uvec3(at.r[0], at.r[1], at.r[2])) != abc) return r;
    r.ok = true;
    r.p = q;
    r.kind = CX_KIND_JUNCTION;
    r.regions = ivec4(ivec3(abc), -1);
    if (!(pc.regions > 3u && at.f[3] - at.f[0] < kCornerBand * s)) return r;
    regs = sort4(uvec4(at.r[0], at.r[1], at.r[2], at.r[3]));
    n = 4u;
  }
  return r;
}

// Where a relaxation pushes particle i before it goes back: along its junction curve's
// tangent, or in its interface's tangent plane (relax_junction, relax_interface in
// complex_step_ref.cpp).
vec3 relaxed(uint i, vec3 p, float s, bool junction, ivec4 regions) {
  vec3 g[4];
  gradients(p, uvec4(regions), junction ? 3u : 2u, g);
  vec3 dir = junction ? cross(g[0] - g[1], g[0] - g[2]) : g[0] - g[1];
  float len = length(dir);
  dir = len > 1e-12 ? dir / len : vec3(0.0);  // the tangent, or the normal from a into b
  vec3 push = vec3(0.0);
  for (uint k = first[i]; k < first[i + 1u]; ++k) {
    uint j = neighbours[k];
    if (j == i) continue;
    vec4 o = in_pos[j];
    float reach = junction ? kRelaxReach * s : kRelaxReach * 0.5 * (s + o.w);
    vec3 d3 = p - o.xyz;
    float d = length(d3);
    if (d < 1e-12 || d >= reach) continue;
    push += (1.0 - d / reach) * d3 / d;
  }
  if (junction) return p + clamp(0.5 * s * dot(push, dir), -kRelaxStepCap * s, kRelaxStepCap * s) * dir;
  vec3 step = 0.5 * s * (push - dir * dot(dir, push));
  float l = length(step);
  if (l > kRelaxStepCap * s) step *= kRelaxStepCap * s / l;
  return p + step;
}

void main() {
  uint i = linear_invocation(pc.row);
  if (i >= pc.count) return;
  vec3 p = in_pos[i].xyz;
  float s = in_pos[i].w;
  ivec4 regions = in_regions[i];
  Result r;
  r.ok = false;
  if (pc.step == CX_STEP_JUNCTION_CANDIDATE) {
    r = junction_candidate_step(p, s);
  } else {
    bool junction = pc.step == CX_STEP_RELAX_JUNCTION, relax = pc.step != CX_STEP_ONTO_INTERFACE;
    if (!relax || in_kind[i] == (junction ? CX_KIND_JUNCTION : CX_KIND_INTERFACE)) {
      vec3 q = relax ? relaxed(i, p, s, junction, regions) : p;
      if (junction) {
        r.ok = project_equal(q, uvec4(regions), 3u, kReach * s);
        r.regions = regions;
        r.kind = CX_KIND_JUNCTION;
      } else {
        uvec2 pair;
        r.ok = onto_interface(q, kReach * s, pair);
        r.regions = ivec4(ivec2(pair), -1, -1);
        r.kind = CX_KIND_INTERFACE;
      }
      r.p = q;
    }
  }
  out_pos[i] = vec4(r.ok ? r.p : p, 0.0);
  out_regions[i] = r.ok ? r.regions : regions;
  out_state[i] = (r.ok ? 1u : 0u) | ((r.ok ? r.kind : in_kind[i]) << 1u);
}
