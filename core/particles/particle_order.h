// The rows of a particle state: their order along a Morton curve, the rows kept, and a
// random tangent for a particle's split.
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <vector>

#include "particles/particle_step_ref.h"

namespace mpumesh::particles {

// The order of the points along a Morton curve over a 1024^3 grid on their bounding box.
std::vector<size_t> morton_order(const std::vector<Eigen::Vector3d>& x);

// Puts the particles in Morton order, so that consecutive particles share MPU leaves and
// neighbours in the cache. Seeding leaves them in the Poisson disk's random order and
// fission appends children at the end; in that order each evaluation and neighbour search
// misses the cache. Both backends get the same order.
void order_spatially(ParticleState& st);

// Keeps the particles `rows` (ascending) in that order, all their per-particle values.
void keep_rows(ParticleState& st, const std::vector<size_t>& rows);

// A tangent direction at angle 2π u in the plane normal to n.
Eigen::Vector3d tangent(const Eigen::Vector3d& n, double u);

}  // namespace mpumesh::particles
