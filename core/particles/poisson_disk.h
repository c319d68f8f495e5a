// Greedy Poisson-disk subsets of points, for the particle system's pool and seeds
// (particle_system.cpp): a point is kept when no point kept before it lies closer than the
// mean of their two radii. The visiting order is a hash of the index and a seed, so the
// subset is repeatable and, for one seed, independent of the thread count.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace mpumesh::particles {

// A random but repeatable visiting order of n points: by a hash of the index and the seed
// (ties by index).
std::vector<uint32_t> hashed_order(size_t n, uint32_t seed);

// The subset, as ascending indices into pts. Visited block by block (blocks of 16³ grid
// cells of the largest radius or a 96th of the points' extent, whichever is larger, from
// the points' lowest corner, in row order; blocks whose results cannot meet run in
// parallel, the subset being the one of that order), each block's points in `order`:
// every kept pair is at least the mean of its radii apart, and every other point lies
// closer than that to a kept one (the subset is maximal). A block's border with the
// blocks done before it packs a little closer than the random order does: on a 60 mm
// sphere at 2 mm radii the sample is 0.4% denser than the plain greedy one (blocks of 8³
// cells: 1.3%, of 4³: 2.3%). radius must be positive and one per point; order a
// permutation of the points' indices.
std::vector<size_t> poisson_disk(const std::vector<Eigen::Vector3d>& pts, const std::vector<double>& radius,
                                 const std::vector<uint32_t>& order);

}  // namespace mpumesh::particles
