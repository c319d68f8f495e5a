// MPU evaluation: f, ∇f and curvature (κ1, κ2, K, mean) at each query point, one
// invocation per point; f and ∇f alone when pc.value_only is set (a uniform branch).
// CPU reference: core/mpu/mpu_eval_ref.cpp (evaluate, curvature).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/mpu_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = MPU_BIND_LEAVES) readonly buffer Leaves { vec4 leaves[]; };
layout(std430, binding = MPU_BIND_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = MPU_BIND_LEAF_IDS) readonly buffer LeafIds { uint leaf_ids[]; };
layout(std430, binding = MPU_BIND_POINTS) readonly buffer Points { vec4 points[]; };
layout(std430, binding = MPU_BIND_FG) writeonly buffer Fg { vec4 fg[]; };
layout(std430, binding = MPU_BIND_CURV) writeonly buffer Curv { vec4 curv[]; };
layout(push_constant) uniform Push { MpuPush pc; };

#include "lib/mpu_eval.glsl"

void main() {
  uint i = linear_invocation(pc.row);
  if (i >= pc.count) return;
  MpuSample s = mpu_evaluate_opt(points[i].xyz, pc.value_only == 0u ? MPU_BLENDED_HESSIAN : MPU_NO_HESSIAN);
  fg[i] = vec4(s.f, s.g);
  if (pc.value_only == 0u) curv[i] = mpu_curvature(s.g, s.H);
}
