// A tetrahedral mesh in millimetres for finite elements: nodes, linear tetrahedra (4
// nodes, positively oriented: (b - a) · ((c - a) × (d - a)) > 0), each tetrahedron's
// region, and the boundary triangles with the region each bounds. Filling one closed
// surface, a region is a connected solid, numbered from 1, and the boundary is the surface,
// outward. Filling a multi-material complex, a region is a label (0 the background, when
// it is meshed) and the boundary is the complex's triangles, each once, with the two
// labels it separates.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace mpumesh {

struct TetMesh {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<uint32_t, 4>> tets;
  std::vector<int32_t> region;  // per tet, 1..regions
  std::vector<std::array<uint32_t, 3>> boundary;
  std::vector<int32_t> boundary_region;  // per boundary triangle
  int32_t regions = 0;                    // how many
  // A complex's (empty for one surface): per boundary triangle the labels (a, b), a < b, of
  // the regions it separates, its normal from a into b; (0, 0) for the faces of the box
  // that bounds a meshed background, facing out. boundary_region is then b (a for the box).
  std::vector<std::array<int32_t, 2>> boundary_labels;

  bool multi_material() const { return !boundary_labels.empty(); }
};

// The faces opposite each vertex, outward for a positively oriented tetrahedron.
inline constexpr int kTetFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// The six dihedral angles (degrees) of abcd, whatever its orientation, in the order of
// the face pairs (0,1), (0,2), (0,3), (1,2), (1,3), (2,3), face k the one opposite
// vertex k.
inline std::array<double, 6> dihedral_angles(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                             const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const Eigen::Vector3d p[4] = {a, b, c, d};
  Eigen::Vector3d n[4];  // unit face normals, all outward or all inward
  for (int k = 0; k < 4; ++k)
    n[k] = (p[kTetFace[k][1]] - p[kTetFace[k][0]]).cross(p[kTetFace[k][2]] - p[kTetFace[k][0]]).normalized();
  // The interior angle between faces i and j: π minus the angle between their normals.
  std::array<double, 6> angle;
  int e = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j, ++e)
      angle[size_t(e)] = 180 - std::acos(std::clamp(n[i].dot(n[j]), -1.0, 1.0)) * 180 / M_PI;
  return angle;
}

}  // namespace mpumesh
