// The angle between two vectors, for the meshes' angle figures and curvature, and a
// solid's angle at an edge of its boundary.
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace mpumesh {

// The angle between two vectors of any lengths (radians), accurate near 0 and pi.
inline double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

// The angle inside a solid at its boundary edge u-v between its two boundary triangles
// there, whose third vertices are w1 and w2, n1 the first triangle's outward normal
// (radians, in [0, 2 pi]): a tetrahedron of the solid on that edge has a dihedral angle
// no larger.
inline double wedge_angle(const Eigen::Vector3d& u, const Eigen::Vector3d& v, const Eigen::Vector3d& w1,
                          const Eigen::Vector3d& w2, const Eigen::Vector3d& n1) {
  const Eigen::Vector3d e = (v - u).normalized();
  auto across = [&](const Eigen::Vector3d& w) {
    const Eigen::Vector3d x = w - u;
    return Eigen::Vector3d(x - e * e.dot(x));
  };
  const Eigen::Vector3d a = across(w1), b = across(w2);
  const double phi = angle_between(a, b);
  return -n1.dot(b) >= 0 ? phi : 2 * 3.14159265358979323846 - phi;
}

}  // namespace mpumesh
