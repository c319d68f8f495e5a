// The MPU implicit surface (Ohtake et al. 2003, with the paper's orthogonal-polynomial
// height fields): leaves of an octree, each a local polynomial in its own frame with a
// spherical support, blended by quadratic B-spline weights:
//   f(x) = Σ w_i(x) Q_i(x) / Σ w_i(x),  w_i = b(3 |x - c_i| / (2 R_i)).
// f < 0 inside, f > 0 outside, ∇f points out; near the surface f is about the signed
// distance in mm. A uniform grid over the bounding cube lists, per cell, the leaves whose
// support ball touches the cell: both backends find a point's leaves through it.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "common/default_init.h"
#include "mpu/local_poly.h"

namespace mpumesh::mpu {

// kTwoSheets: the two faces of a plate or gap thinner than the ball (local_fit.h).
enum class FitKind : uint8_t { kHeightOrthopoly = 0, kHeightQuadric = 1, kGeneralQuadric = 2, kTwoSheets = 3 };

struct Leaf {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1;                                   // support radius R, mm
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  // rows: u, v, w axes
  Coeffs coeffs{};                                     // of q(y), y = frame (x - c) / R
  FitKind kind = FitKind::kHeightOrthopoly;
  uint8_t degree = 2;   // of the height field (2 for quadrics)
  uint8_t depth = 0;    // octree level
  uint32_t points = 0;  // points in the support ball when fitted
};

struct LookupGrid {
  std::array<uint32_t, 3> dims{1, 1, 1};
  std::vector<uint32_t> offsets;  // cells + 1, CSR into leaf_ids
  FillVector<uint32_t> leaf_ids;  // (filled in parallel: common/default_init.h)
  // Per leaf: centre and R², a compact copy (32 B per leaf instead of ~280) for the
  // support test that most candidates fail; not stored in the file, rebuilt on reading.
  std::vector<Eigen::Vector4d> spheres;
  // Per leaf, when the evaluation runs in single precision (common/eval_precision.h): its
  // first kRecord32 doubles (centre, radius, frame column-major, coefficients, padding)
  // as floats, for the float kernels; empty otherwise. Rebuilt with the spheres.
  static constexpr size_t kRecord32 = 36;
  std::vector<float> records32;
};

struct MpuSurface {
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();  // the bounding cube
  double box_size = 1;
  // The fitted points' bounding box, inside the cube: where the surface lies.
  Eigen::Vector3d data_min = Eigen::Vector3d::Zero(), data_max = Eigen::Vector3d::Zero();
  std::vector<Leaf> leaves;
  LookupGrid grid;
  double cell_size() const { return box_size / double(grid.dims[0]); }
};

// Builds the lookup grid: `cells_per_side` cells along each axis of the bounding cube
// (and the spheres).
void build_lookup_grid(MpuSurface& s, uint32_t cells_per_side);
// Fills grid.spheres (and grid.records32 in single precision) from the leaves.
void index_spheres(MpuSurface& s);

}  // namespace mpumesh::mpu
