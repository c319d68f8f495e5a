// The circumcentre of a tetrahedron, bit for bit as CGAL's Robust_circumcenter_traits_3
// over Epick constructs it (Epeck's lazy construction read back with to_double: within
// Epeck's relative precision of to_double of the exact point, also for a flat one), but
// without Epeck's allocations where they are not needed: first the interval construction
// that the lazy kernel makes, under the same rounding, read as the lazy kernel reads it
// (each coordinate's midpoint, when it is known to that precision); the lazy kernel itself
// only where a coordinate is not, and it would compute the point exactly. On the sample
// CT's 356,000 cells the interval construction always sufficed, and took a third of the
// robust construction's time.
#pragma once

#include <Eigen/Dense>

namespace mpumesh {

Eigen::Vector3d robust_circumcentre(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                    const Eigen::Vector3d& d);

}  // namespace mpumesh
