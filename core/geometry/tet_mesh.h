// A tetrahedral mesh in millimetres for finite elements: nodes, linear tetrahedra (4
// nodes, positively oriented: (b - a) · ((c - a) × (d - a)) > 0), each tetrahedron's
// region (a connected solid, numbered from 1), and the boundary triangles (outward, the
// surface the mesh fills) with the region each bounds.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

namespace mpumesh {

struct TetMesh {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<uint32_t, 4>> tets;
  std::vector<int32_t> region;  // per tet, 1..regions
  std::vector<std::array<uint32_t, 3>> boundary;
  std::vector<int32_t> boundary_region;  // per boundary triangle
  int32_t regions = 0;
};

}  // namespace mpumesh
