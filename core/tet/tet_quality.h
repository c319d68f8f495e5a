// The shape of a tetrahedral mesh, as finite-element users judge it: each tetrahedron's
// six dihedral angles (between its faces, inside it), its radius ratio 3 r_in / r_circ (1
// for the regular tetrahedron, 0 for a flat one) and its signed volume.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/tet_mesh.h"

namespace mpumesh {

struct TetShape {
  double volume = 0;  // signed, mm³ (positive for a positively oriented tetrahedron)
  double min_dihedral_deg = 0, max_dihedral_deg = 0;
  double radius_ratio = 0;
};
// dihedral_angles: geometry/tet_mesh.h.
TetShape tet_shape(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d);

struct TetQuality {
  int64_t nodes = 0, tets = 0, regions = 0, boundary_triangles = 0;
  int64_t inverted = 0;  // volume <= 0
  double volume_mm3 = 0;
  double min_dihedral_deg = 0, max_dihedral_deg = 0;
  double pct_min_dihedral_below_10 = 0, pct_min_dihedral_below_15 = 0;  // of the tets
  double radius_ratio_mean = 0, radius_ratio_min = 0;
  // Every dihedral angle (six a tet) in 5° bins from 0 to 180.
  std::array<int64_t, 36> dihedral_histogram{};
};
TetQuality measure_tet_quality(const TetMesh& m);

}  // namespace mpumesh
