// Particle repulsion (eq. 11, 12 with Witkin–Heckbert's projection and σ update), one
// invocation per particle: energy, velocity, the linearly implicit move and σ step.
// CPU reference: repulsion_step in core/particles/particle_step_ref.cpp, which documents
// the formulas.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/particle_step_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = PT_BIND_POS) readonly buffer Pos { vec4 pos[]; };
layout(std430, binding = PT_BIND_POS_NEW) writeonly buffer PosNew { vec4 pos_new[]; };
layout(std430, binding = PT_BIND_NORMAL) readonly buffer Normal { vec4 normal[]; };
layout(std430, binding = PT_BIND_STATS) writeonly buffer Stats { vec4 stats[]; };
layout(std430, binding = PT_BIND_CELL) readonly buffer Cell { uint cell_of[]; };
layout(std430, binding = PT_BIND_START) readonly buffer Start { uint start[]; };
layout(std430, binding = PT_BIND_ORDER) readonly buffer Order { uint order[]; };
layout(push_constant) uniform Push { ParticlePush pc; };

void main() {
  uint i = linear_invocation(pc.row);
  if (i >= pc.count) return;
  vec3 xi = pos[i].xyz;
  float si = pos[i].w, inv_si2 = 1.0 / (si * si);
  float c2 = pc.cutoff * pc.cutoff;
  uint cell = cell_of[i];
  int cx = int(cell % pc.gx), cy = int((cell / pc.gx) % pc.gy), cz = int(cell / (pc.gx * pc.gy));
  float E = 0.0, dE = 0.0, stiff = 0.0;
  vec3 D = vec3(0.0);
  for (int z = max(cz - 1, 0); z <= min(cz + 1, int(pc.gz) - 1); ++z)
    for (int y = max(cy - 1, 0); y <= min(cy + 1, int(pc.gy) - 1); ++y) {
      uint row = pc.gx * (uint(y) + pc.gy * uint(z));
      uint first = start[row + uint(max(cx - 1, 0))], last = start[row + uint(min(cx + 1, int(pc.gx) - 1)) + 1u];
      for (uint k = first; k < last; ++k) {
        uint j = order[k];
        if (j == i) continue;
        vec4 pj = pos[j];
        float sj = pj.w, inv_sj2 = 1.0 / (sj * sj);
        vec3 r = xi - pj.xyz;
        float r2 = dot(r, r);
        float eij = r2 < c2 * si * si ? pc.mu * exp(-0.5 * r2 * inv_si2) : 0.0;
        float eji = r2 < c2 * sj * sj ? pc.mu * exp(-0.5 * r2 * inv_sj2) : 0.0;
        E += eij + eji;
        dE += r2 * inv_si2 / si * eij;
        float a = eij * inv_si2 + eji * inv_sj2;
        D += r * a;
        stiff += max(r2 * (eij * inv_si2 * inv_si2 + eji * inv_sj2 * inv_sj2) - a, 0.0);
      }
    }
  D *= si * si;
  vec3 n = normal[i].xyz;
  float dist = isnan(normal[i].w) ? 0.0 : normal[i].w;
  vec3 v = D - (dot(n, D) + pc.phi * dist) * n;
  float k = 0.5 * si * si * stiff;
  vec3 step = pc.dt / (1.0 + pc.dt * k) * v;
  float len = length(step), cap = pc.max_move * si;
  if (len > cap) step *= cap / len;
  float dsigma = -pc.dt * pc.rho * (E - pc.desired_energy) / (dE + pc.beta + pc.dt * pc.rho * dE);
  float s_new = min(clamp(si + dsigma, si / pc.sigma_change, si * pc.sigma_change), pc.sigma_cap);
  pos_new[i] = vec4(xi + step, s_new);
  stats[i] = vec4(E, length(v), 0.0, 0.0);
}
