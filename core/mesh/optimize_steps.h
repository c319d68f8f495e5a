// The steps of the mesh optimisation (mesh/mesh_optimize.h), private to its files: the
// flips (steps 1 and 5, mesh/optimize_flips.cpp), the flat caps and the polish (step 4,
// mesh/optimize_polish.cpp), and the helpers they share with the relaxation and the
// collapses (mesh/mesh_optimize.cpp).
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <span>
#include <vector>

#include "compute/compute_backend.h"
#include "mesh/edge_edit.h"
#include "mesh/mesh_optimize.h"
#include "mpu/mpu_surface.h"
#include "particles/particle_step_ref.h"

namespace mpumesh::optimize {

// The triangle's normal times twice its area.
inline Eigen::Vector3d area_normal(const std::vector<Eigen::Vector3d>& x, const Tri& t) {
  return (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
}

// Whether a triangle whose normal was old_n (of any length) and is new_n after a change is
// still a triangle, turned by no more than acos(cos_turn).
bool turned_within(const Eigen::Vector3d& old_n, const Eigen::Vector3d& new_n, double cos_turn);
// The points of `st` onto f = 0 on the backend: opt.newton_steps Newton steps, each
// moving a point at most its sigma.
void project_onto_surface(const mpu::MpuSurface& s, ComputeBackend& backend, particles::ParticleState& st,
                          const OptimizeOptions& opt);
// Whether point i of a projection reached f = 0 (within a thousandth of its sigma).
bool landed(const particles::ParticleState& st, size_t i);
// The smallest angle (degrees) of the triangles `faces` with the vertices at x.
double smallest_angle(const std::vector<Eigen::Vector3d>& x, const std::vector<Tri>& T,
                      std::span<const uint32_t> faces);

// Step 1: one pass of Delaunay flips, applied; returns them.
std::vector<FlipRecord> flip_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                                  const OptimizeOptions& opt, const FrozenVertices& frozen);
// Step 5: one pass of flips for smoothness, applied; returns how many were kept.
int64_t smoothing_flip_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                            const OptimizeOptions& opt, const FrozenVertices& frozen);
// Step 4: the flat caps removed (returns how many), then one polish pass (returns the
// moves made).
int64_t remove_flat_caps(TriangleMesh& m, const OptimizeOptions& opt, const FrozenVertices& frozen);
int64_t polish_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                    const std::vector<double>& spacing, const OptimizeOptions& opt, const FrozenVertices& frozen);

}  // namespace mpumesh::optimize
