// A bound on how fast the particles' target spacing may change along the surface.
//
// The targets s_i = min(h λ_i, thickness) jump where a thin plate meets a thick one, or a
// sharp bend a flat patch: on the sample CT from 1.5 mm to 6.8 mm between neighbours.
// Particles at their targets then put a short edge beside two long ones, and the
// restricted Delaunay triangles there are needles (the mesh's smallest angles, 14-18°,
// sat at such steps on the zygomatic arches). Size fields for meshing are graded for
// this reason (Persson 2006, "Mesh size functions for implicit geometries and PDE-based
// gradient limiting"): afterwards
//     s_i <= s_j + grade · |x_i - x_j|
// for every pair of neighbours, and so, through chains of neighbours, about along the
// surface. Targets only ever go down.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace mpumesh::particles {

// Neighbours: points closer than min(link · s_i, max_reach) to point i (s_i its initial
// target), in either direction. The bound is exact over that graph (Dijkstra from the
// smallest target). max_reach keeps the graph small where the points are much denser
// than their targets (the seeding pool): a chain of near neighbours carries the bound as
// far. Returns how many targets it lowered.
size_t limit_spacing_gradient(const std::vector<Eigen::Vector3d>& x, std::vector<double>& spacing, double grade,
                              double max_reach = INFINITY, double link = 1.5);

}  // namespace mpumesh::particles
