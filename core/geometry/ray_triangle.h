// Where a ray meets a triangle (Möller and Trumbore 1997): the distance along the ray from
// o in units of d, when the line o + t d crosses the triangle abc (its edges included) and
// the triangle is not edge-on to d; nothing otherwise. t may be negative (behind o).
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <optional>

namespace mpumesh {

inline std::optional<double> ray_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-14) return std::nullopt;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(h) / det;
  if (u < 0 || u > 1) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0 || u + v > 1) return std::nullopt;
  return e2.dot(q) / det;
}

}  // namespace mpumesh
