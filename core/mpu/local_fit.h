// The local fits of one MPU cell, over the points in its support ball:
// - a height field w - h(u, v) over the plane ⟂ the weighted mean normal, h built from
//   polynomials orthogonal over the ball's points (the paper's eq. 7-8: Gram-Schmidt on
//   the monomials with the B-spline-weighted inner product, so no normal equations are
//   solved), its degree rising from 2 while the points support it and the error falls;
//   optionally (FitOptions::fit_normals) fitting the points' normals as its slopes too, in
//   the same inner product (a Hermite fit), which pins it between the slices of a stack;
// - Ohtake's bivariate quadric height field by weighted normal equations (the original);
// - a general quadric in 3D, fitted with Ohtake's auxiliary points (cell corners and
//   centre with an estimated signed distance) so that it is not the trivial zero.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "mpu/mpu_surface.h"
#include "geometry/point_cloud.h"

namespace mpumesh::mpu {

struct Ball {
  Eigen::Vector3d centre;
  double radius;
  std::vector<uint32_t> ids;  // points inside
};

struct AuxPoint {
  Eigen::Vector3d position;
  double distance;  // estimated signed distance (mm)
};

// Taubin's first-order distance, max over the ball's points: |Q| / |∇Q| (mm).
double taubin_error(const Leaf& leaf, const Ball& ball, const PointCloud& cloud);

// The B-spline-weighted mean normal of the ball (not normalised).
Eigen::Vector3d mean_normal(const Ball& ball, const PointCloud& cloud);

// A right-handed frame whose third row is n (unit).
Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& n);

// Height fields; `degree_cap` caps the orthopoly degree (2..4); slope_length > 0 (mm) fits
// the points' normals too (local_fit.cpp). Each returns the leaf with its error.
Leaf fit_height_orthopoly(const Ball& ball, const PointCloud& cloud, const Eigen::Vector3d& normal, int degree_cap,
                          double slope_length, double* error);
Leaf fit_height_quadric(const Ball& ball, const PointCloud& cloud, const Eigen::Vector3d& normal, double* error);
Leaf fit_general_quadric(const Ball& ball, const PointCloud& cloud, const std::vector<AuxPoint>& aux, double* error);

}  // namespace mpumesh::mpu
