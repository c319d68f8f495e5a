// The angle between two vectors, for the meshes' angle figures and curvature.
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace mpumesh {

// The angle between two vectors of any lengths (radians), accurate near 0 and pi.
inline double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace mpumesh
