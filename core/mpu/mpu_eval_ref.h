// Evaluation of the MPU surface: f, ∇f and the Hessian, analytic (the CPU reference of
// shaders/mpu_eval.comp), and curvature after Kindlmann et al. (2003):
//   n = g / |g|, P = I - n nᵀ, G = -P H P / |g|, T = tr G, F = ‖G‖_F,
//   κ1,2 = (T ± √(2F² - T²)) / 2, K = κ1 κ2, mean = (κ1 + κ2) / 2.
// A point that no leaf's support holds (outside the bounding cube) gets f = the cube's
// size (outside, far), ∇f = 0, H = 0 and zero curvature.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

struct Sample {
  double f = 0;
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  int leaves = 0;  // leaves whose support holds the point
};

struct Curvature {
  double k1 = 0, k2 = 0, gauss = 0, mean = 0;  // 1/mm, 1/mm², 1/mm; k1 >= k2
};

Sample evaluate(const MpuSurface& s, const Eigen::Vector3d& x);
// f and ∇f only (H left zero): what projection onto f = 0 needs.
Sample evaluate_fg(const MpuSurface& s, const Eigen::Vector3d& x);
// f alone (no derivatives), for polygonization.
double evaluate_f(const MpuSurface& s, const Eigen::Vector3d& x);
Curvature curvature(const Eigen::Vector3d& g, const Eigen::Matrix3d& H);

// The points' indices in the order of their lookup-grid cells: evaluated in that order,
// consecutive points share their leaves in the cache (a surface of 10^5 leaves is tens of
// MB; in random order each leaf read misses it). The results do not depend on the order.
std::vector<size_t> cache_order(const MpuSurface& s, const std::vector<Eigen::Vector3d>& points);

// Many points, in parallel: one row per point, x y z f gx gy gz k1 k2 K H (the layout of
// `mpumesh eval`).
struct EvalRow {
  double x[3], f, g[3], k1, k2, gauss, mean;
};
std::vector<EvalRow> evaluate_all(const MpuSurface& s, const std::vector<Eigen::Vector3d>& points);

}  // namespace mpumesh::mpu
