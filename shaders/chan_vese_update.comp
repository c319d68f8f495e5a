// Chan-Vese, pass 2 of an iteration: one semi-implicit Jacobi step per pixel, phi_in to
// phi_out, every slice in one dispatch (the scheme is written out in
// core/segment/chan_vese_ref.h). Neighbour indices are clamped: Neumann borders.
// CPU reference: core/segment/chan_vese_ref.cpp (chan_vese_step).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/chan_vese_abi.h"
#include "lib/invocation.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = CV_BIND_U) readonly buffer U { float u[]; };
layout(std430, binding = CV_BIND_PHI_IN) readonly buffer PhiIn { float phi_in[]; };
layout(std430, binding = CV_BIND_PHI_OUT) writeonly buffer PhiOut { float phi_out[]; };
layout(std430, binding = CV_BIND_MEANS) readonly buffer Means { vec4 means[]; };
layout(push_constant) uniform Push { CvPush pc; };

const float kInvPi = 0.31830988618379067;

void main() {
  uint p = linear_invocation(pc.row);
  uint n = pc.nx * pc.ny;
  if (p >= n * pc.nz) return;
  uint k = p / n;
  uint r = p - k * n;
  uint j = r / pc.nx;
  uint i = r - j * pc.nx;
  uint base = k * n;
  uint im = i > 0u ? i - 1u : 0u, ip = min(i + 1u, pc.nx - 1u);
  uint jm = j > 0u ? j - 1u : 0u, jp = min(j + 1u, pc.ny - 1u);
  float c = phi_in[p];
  float xp = phi_in[base + ip + pc.nx * j], xm = phi_in[base + im + pc.nx * j];
  float yp = phi_in[base + i + pc.nx * jp], ym = phi_in[base + i + pc.nx * jm];
  float xm_yp = phi_in[base + im + pc.nx * jp], xm_ym = phi_in[base + im + pc.nx * jm];
  float xp_ym = phi_in[base + ip + pc.nx * jm];

  float eta2 = pc.eta * pc.eta;
  float d;
  float e;
  d = xp - c; e = (yp - ym) * 0.5;
  float C1 = 1.0 / sqrt(eta2 + d * d + e * e);
  d = c - xm; e = (xm_yp - xm_ym) * 0.5;
  float C2 = 1.0 / sqrt(eta2 + d * d + e * e);
  d = (xp - xm) * 0.5; e = yp - c;
  float C3 = 1.0 / sqrt(eta2 + d * d + e * e);
  d = (xp_ym - xm_ym) * 0.5; e = c - ym;
  float C4 = 1.0 / sqrt(eta2 + d * d + e * e);

  float delta = pc.epsilon * kInvPi / (pc.epsilon * pc.epsilon + c * c);
  float m = pc.dt * delta * pc.mu;
  vec4 cm = means[k];
  float uv = u[p];
  float force = -pc.nu - pc.lambda1 * (uv - cm.x) * (uv - cm.x) + pc.lambda2 * (uv - cm.y) * (uv - cm.y);
  float num = c + m * (C1 * xp + C2 * xm + C3 * yp + C4 * ym) + pc.dt * delta * force;
  phi_out[p] = num / (1.0 + m * (C1 + C2 + C3 + C4));
}
