// Local thickness at each particle: the distance along -n (through the inside) or +n
// (across a gap) to the nearest other sheet of f = 0, up to a per-particle reach; +inf
// when none is that near. Sampled at THICKNESS_STEPS even steps, the bracketing step
// narrowed by THICKNESS_BISECTIONS bisections. CPU reference: local_thickness in
// core/particles/particle_step_ref.cpp (kThicknessSteps, kThicknessBisections there).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/particle_step_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = MPU_BIND_LEAVES) readonly buffer Leaves { vec4 leaves[]; };
layout(std430, binding = MPU_BIND_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = MPU_BIND_LEAF_IDS) readonly buffer LeafIds { uint leaf_ids[]; };
layout(std430, binding = PT_BIND_POS) readonly buffer Pos { vec4 pos[]; };            // x, reach
layout(std430, binding = PT_BIND_NORMAL) readonly buffer Normal { vec4 normal[]; };   // n
layout(std430, binding = PT_BIND_STATS) writeonly buffer Stats { vec4 stats[]; };     // thickness
layout(push_constant) uniform Push { ParticlePush pc; };

#include "lib/mpu_eval.glsl"

const int THICKNESS_STEPS = 4, THICKNESS_BISECTIONS = 5;

// Past the far sheet, t along dir · n from x: inward (dir < 0) f is negative until the
// opposite sheet, outward positive until the next one.
bool crossed(vec3 x, vec3 n, float dir, float t) { return dir * mpu_evaluate_opt(x + dir * t * n, MPU_NO_HESSIAN).f < 0.0; }

void main() {
  uint i = linear_invocation(pc.row);
  if (i >= pc.count) return;
  vec3 x = pos[i].xyz, n = normal[i].xyz;
  float max_dist = pos[i].w;
  float best = uintBitsToFloat(0x7f800000u);  // +inf
  if (max_dist > 0.0 && !isinf(max_dist)) {
    for (int di = 0; di < 2; ++di) {
      float dir = di == 0 ? -1.0 : 1.0;
      float step = min(best, max_dist) / float(THICKNESS_STEPS);
      for (int k = 1; k <= THICKNESS_STEPS; ++k) {
        float t = float(k) * step;
        if (!crossed(x, n, dir, t)) continue;
        float a = float(k - 1) * step, b = t;
        for (int it = 0; it < THICKNESS_BISECTIONS; ++it) {
          float m = 0.5 * (a + b);
          if (crossed(x, n, dir, m)) b = m;
          else a = m;
        }
        best = min(best, 0.5 * (a + b));
        break;
      }
    }
  }
  stats[i] = vec4(best, 0.0, 0.0, 0.0);
}
