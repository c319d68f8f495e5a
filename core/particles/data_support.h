// Where the data are: whether a point lies within a reach of the candidate points (the
// fitted points, from which the particles are seeded).
//
// An MPU fit can have a spurious sheet of f = 0 away from every point, where only the
// polynomials of leaves that had to grow their balls reach (on the sample CT: a closed
// sheet 17-24 mm from any point, in the air by the volume's cut face). Particles that
// slide onto it are sampling nothing the data say; the particle system removes those
// farther than the reach from every candidate.
//
// The candidates bucketed in a grid of cells at least the reach wide; near() looks in the
// 27 cells around the point, its own first, and stops at the first candidate within the
// reach (on the surface that is one of the first few it sees). Exact: true if and only if
// some candidate lies within `reach`.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

namespace mpumesh::particles {

class DataSupport {
 public:
  // At most `max_cells` cells along an axis (the cells grow where the box is large).
  DataSupport(const std::vector<Eigen::Vector3d>& candidates, double reach, int max_cells = 128);
  bool near(const Eigen::Vector3d& x) const;

 private:
  const std::vector<Eigen::Vector3d>* points_;
  Eigen::Vector3d lo_;
  double cell_ = 1, reach_ = 0;
  std::array<int64_t, 3> dims_{1, 1, 1};
  std::vector<uint32_t> first_, ids_;  // compressed rows: the candidates of each cell
};

}  // namespace mpumesh::particles
