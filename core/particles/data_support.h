// Where the data are: which points lie within a reach of the candidate points (the
// fitted points, from which the particles are seeded).
//
// An MPU fit can have a spurious sheet of f = 0 away from every point, where only the
// polynomials of leaves that had to grow their balls reach (on the sample CT: a closed
// sheet 17-24 mm from any point, in the air by the volume's cut face). Particles that
// slide onto it are sampling nothing the data say; the particle system removes those
// farther than the reach from every candidate.
//
// A boolean grid over the candidates' bounding box (widened by the reach), of cells at
// least half the reach wide: a cell is on when it lies within ceil(reach / cell) cells of
// a candidate's cell along every axis. Every point within `reach` of a candidate is then
// near, and none farther than √3 (ceil(reach / cell) + 1) cells from every candidate:
// √3 (reach + cell) when the reach is a whole number of cells, under √3 (reach + 2 cell)
// always.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

namespace mpumesh::particles {

class DataSupport {
 public:
  // At most `max_cells` cells along an axis (the cell grows where the box is large).
  DataSupport(const std::vector<Eigen::Vector3d>& candidates, double reach, int max_cells = 256);
  bool near(const Eigen::Vector3d& x) const;
  double reach() const { return reach_; }

 private:
  Eigen::Vector3d lo_;
  double cell_ = 1, reach_ = 0;
  std::array<int64_t, 3> dims_{1, 1, 1};
  std::vector<uint8_t> on_;
};

}  // namespace mpumesh::particles
