// Data contract of the particle kernels (particle_step_grid_count.comp,
// particle_step_grid_scatter.comp, particle_step_repulsion.comp, particle_step_project.comp,
// particle_step_thickness.comp) and their CPU reference (core/particles/particle_step_ref.cpp). Positions are relative to the MPU
// surface's origin (host/kernels/mpu_eval_vk.h), as in mpu_eval.comp; bindings 0-2 are
// the surface's leaves, offsets and leaf ids. Per particle:
//   pos     vec4 (x, y, z, σ)           the state
//   pos_new vec4 (x', y', z', σ')       after repulsion, before projection
//   normal  vec4 (n, d)                 ∇f/|∇f| and f/|∇f| after projection (d NaN: lost)
//   curv    vec4 (κ1, κ2, K, H)         after projection, when push.curvature is set
//   stats   vec4 (E, |ṗ|, 0, 0)         from repulsion
// particle_step_thickness.comp reads pos as (x, y, z, reach) and normal's n, and writes the
// thickness (+inf: no other sheet within reach) to stats.x.
// The neighbour grid: cell and rank (within its cell) per particle, start[cells + 1]
// (counts, then their exclusive scan), order[] (particles by cell).
#ifndef MPUMESH_PARTICLE_ABI_H
#define MPUMESH_PARTICLE_ABI_H
#include "shared/abi_prelude.h"
#include "shared/mpu_abi.h"

#define PT_BIND_POS 3
#define PT_BIND_POS_NEW 4
#define PT_BIND_NORMAL 5
#define PT_BIND_CURV 6
#define PT_BIND_STATS 7
#define PT_BIND_CELL 8
#define PT_BIND_RANK 9
#define PT_BIND_START 10
#define PT_BIND_ORDER 11

ABI_BEGIN
// The first ten fields carry MpuPush's names, which lib/mpu_eval.glsl reads.
struct ParticlePush {
  float box_min_x, box_min_y, box_min_z;
  float inv_cell;
  uint nx, ny, nz;
  float far_value;
  uint count;  // particles
  uint row;    // invocations per dispatch row
  float grid_x, grid_y, grid_z;  // neighbour grid origin (relative to the surface origin)
  float grid_inv_cell;
  uint gx, gy, gz;               // neighbour grid dims
  float dt, mu, desired_energy, rho, beta, phi, cutoff, max_move, sigma_change, sigma_cap;
  uint newton_steps;
  uint curvature;  // 1: measure the curvature (last iteration of a batch)
};
ABI_END

#ifdef __cplusplus
static_assert(sizeof(mpumesh::abi::ParticlePush) == 116, "ParticlePush must match the GLSL push block");
#endif
#endif
