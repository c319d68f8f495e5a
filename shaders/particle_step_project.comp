// Particle projection onto f = 0: Newton steps x -= f ∇f / |∇f|² (each capped at σ), the
// last from the full evaluation (f, ∇f, H) that also gives normal and curvature. CPU reference: project_step in
// core/particles/particle_step_ref.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/particle_step_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = MPU_BIND_LEAVES) readonly buffer Leaves { vec4 leaves[]; };
layout(std430, binding = MPU_BIND_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = MPU_BIND_LEAF_IDS) readonly buffer LeafIds { uint leaf_ids[]; };
layout(std430, binding = PT_BIND_POS) writeonly buffer Pos { vec4 pos[]; };
layout(std430, binding = PT_BIND_POS_NEW) readonly buffer PosNew { vec4 pos_new[]; };
layout(std430, binding = PT_BIND_NORMAL) writeonly buffer Normal { vec4 normal[]; };
layout(std430, binding = PT_BIND_CURV) writeonly buffer Curv { vec4 curv[]; };
layout(push_constant) uniform Push { ParticlePush pc; };

#include "lib/mpu_eval.glsl"

void main() {
  uint i = linear_invocation(pc.row);
  if (i >= pc.count) return;
  vec3 x = pos_new[i].xyz;
  float sigma = pos_new[i].w;
  bool ok = true;
  for (uint k = 0u; k + 1u < pc.newton_steps; ++k) {
    MpuSample s = mpu_evaluate_opt(x, MPU_NO_HESSIAN);
    float g2 = dot(s.g, s.g);
    ok = ok && g2 > 0.0 && s.leaves > 0u;
    vec3 step = ok ? -s.f / g2 * s.g : vec3(0.0);
    float len = length(step);
    if (len > sigma) step *= sigma / len;
    x += step;
  }
  // The last Newton step from the evaluation that also gives the normal, and the Hessian
  // of f for the curvature weights on a batch's last iteration (as the CPU reference).
  MpuSample s = mpu_evaluate_opt(x, pc.curvature != 0u ? MPU_HESSIAN : MPU_NO_HESSIAN);
  float g2 = dot(s.g, s.g), g = sqrt(g2);
  if (!ok || !(g > 0.0) || s.leaves == 0u) {
    pos[i] = vec4(x, sigma);
    normal[i] = vec4(0.0, 0.0, 1.0, uintBitsToFloat(0x7fc00000u));  // lost
    // A NaN evaluation (a broken surface or kernel) is told from a vanished gradient by
    // NaN curvature, which the driver's finiteness check reports.
    const bool nan_eval = isnan(s.f) || any(isnan(s.g));
    if (pc.curvature != 0u) curv[i] = nan_eval ? vec4(uintBitsToFloat(0x7fc00000u)) : vec4(0.0);
    return;
  }
  vec3 step = -s.f / g2 * s.g;
  float len = length(step);
  if (len > sigma) step *= sigma / len;
  pos[i] = vec4(x + step, sigma);
  normal[i] = vec4(s.g / g, (s.f + dot(s.g, step)) / g);
  if (pc.curvature != 0u) curv[i] = mpu_curvature(s.g, s.H);
}
