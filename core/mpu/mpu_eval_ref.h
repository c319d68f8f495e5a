// Evaluation of the MPU surface: f, ∇f and second derivatives, analytic (the CPU
// reference of shaders/mpu_eval.comp), and curvature after Kindlmann et al. (2003):
//   n = g / |g|, P = I - n nᵀ, G = -P H P / |g|, T = tr G, F = ‖G‖_F,
//   κ1,2 = (T ± √(2F² - T²)) / 2, K = κ1 κ2, mean = (κ1 + κ2) / 2.
//
// Two second derivatives. The Hessian of f = Σ w_i Q_i / Σ w_i itself,
//   H = Σ (w_i ∇²Q_i + ∇w_i ∇Q_iᵀ + ∇Q_i ∇w_iᵀ + (Q_i - f) ∇²w_i) / Σ w_i - (∇f ∇Dᵀ + ∇D ∇fᵀ) / D,
// carries the leaves' disagreement (Q_i - f, ∇Q_i - ∇f, a fraction of eps near the
// surface) through the weights' derivatives, which grow as 1/R and 1/R²: on the
// analytic phantoms those terms, not the fits, made most of the curvature error. The
// curvature takes the blended Hessian instead, the weighted mean of the leaves' own:
//   Hb = Σ w_i ∇²Q_i / Σ w_i,
// the "diffuse derivative" of moving least squares (Nayroles, Touzot & Villon 1992), which
// converges to the surface's second derivatives as the fits do, without the blending's
// wiggles: K within 2.3-3.6% (p95) of the analytic value on the phantoms, 6.2% on the
// ellipsoid as a 2 mm slice stack (tests/core/mpu/test_mpu_fit.cpp). (The particles'
// curvature weights keep the Hessian of f: core/particles/particle_step_ref.h says why.)
//
// A point that no leaf's support holds (outside the bounding cube) gets f = the cube's
// size (outside, far), ∇f = 0, zero second derivatives and zero curvature.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

struct Sample {
  double f = 0;
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  Eigen::Matrix3d Hb = Eigen::Matrix3d::Zero();  // blended Hessian (evaluate, evaluate_hessian), 1/mm
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();   // Hessian of f (evaluate_hessian only), 1/mm
  int leaves = 0;  // leaves whose support holds the point
};

struct Curvature {
  double k1 = 0, k2 = 0, gauss = 0, mean = 0;  // 1/mm, 1/mm², 1/mm; k1 >= k2
};

// f, ∇f and Hb: what the curvature needs.
Sample evaluate(const MpuSurface& s, const Eigen::Vector3d& x);
// f, ∇f, Hb and the Hessian H of f.
Sample evaluate_hessian(const MpuSurface& s, const Eigen::Vector3d& x);
// f and ∇f only (Hb and H left zero): what projection onto f = 0 needs.
Sample evaluate_fg(const MpuSurface& s, const Eigen::Vector3d& x);
// f alone (no derivatives), for polygonization.
double evaluate_f(const MpuSurface& s, const Eigen::Vector3d& x);
// Kindlmann's formulas for the gradient g and a second derivative H.
Curvature curvature(const Eigen::Vector3d& g, const Eigen::Matrix3d& H);
// The surface's curvature at an evaluated point: from ∇f and the blended Hessian.
inline Curvature curvature(const Sample& e) { return curvature(e.g, e.Hb); }

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
