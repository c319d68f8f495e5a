// The local fits of one MPU cell, over the points in its support ball:
// - a height field w - h(u, v) over the plane ⟂ the weighted mean normal, h built from
//   polynomials orthogonal over the ball's points (the paper's eq. 7-8: Gram-Schmidt on
//   the monomials with the B-spline-weighted inner product, so no normal equations are
//   solved), its degree rising from 2 while the points support it and the error falls;
//   optionally (FitOptions::fit_normals) fitting the points' normals as its slopes too, in
//   the same inner product (a Hermite fit), which pins it between the slices of a stack;
// - Ohtake's bivariate quadric height field by weighted normal equations (the original);
// - a general quadric in 3D, fitted with Ohtake's auxiliary points (cell corners and
//   centre with an estimated signed distance) so that it is not the trivial zero;
// - two sheets, for a ball that holds both faces of a plate (or gap) thinner than it: a
//   quadric height field for each face, joined in one function that is zero on both
//   (fit_two_sheets, below). A single general quadric can hold two parallel planes but
//   not two curved sheets: on a 2.5 mm spherical shell its normals are off by 1.2° with
//   exact points and 4° with a CT's.
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

// Taubin's first-order distance |Q| / |∇Q| (mm), each point's divided by its tolerance
// (PointCloud::tolerance), max over the ball's points.
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

// The points split by the side their normals face along the normals' axis (the principal
// direction of Σ weight n nᵀ, the frame's w), a quadric height field a(u, v) fitted to
// those facing +w and b(u, v) to those facing -w, and
//     q = (w - a)(w - b) / t,   t = the weighted mean of a - b over the points:
// zero on both sheets with |∇q| = |a - b| / |t| ≈ 1 there (about a signed distance),
// negative between them where a > b (a plate: its faces look away from each other) and
// positive where a < b (a gap: they face each other), and its curvature on each sheet
// that sheet's (the other factor only scales ∇q and adds a term along it). Error infinite
// (not usable) when a side has fewer than kMinSheetPoints points, more than a tenth of
// the weight has normals within 60° of the plane ⟂ the axis (not two faces), or a - b
// changes sign or falls under a fifth of |t| at a point (the faces cross or touch).
inline constexpr int kMinSheetPoints = 10;
Leaf fit_two_sheets(const Ball& ball, const PointCloud& cloud, double* error);

}  // namespace mpumesh::mpu
