// The MPU evaluation's second derivatives (core/mpu/mpu_eval_ref.h): the blended Hessian
// Hb = Σ w_i ∇²Q_i / Σ w_i against its definition on hand-built leaves whose functions are
// known in closed form, the Hessian H of f against central differences of ∇f (on those
// leaves and on a fitted phantom), and the two agreeing where every leaf holds the same
// function.
#include <gtest/gtest.h>

#include <random>

#include "mpu/mpu_eval_ref.h"
#include "mpu/mpu_fit.h"
#include "test_support.h"

namespace mpumesh {
namespace {

constexpr double kR0 = 10;  // the sphere that every hand-built leaf holds, mm

struct HandLeaf {
  Eigen::Vector3d centre;
  double radius, bend;  // Q(x) = (|x|² - r0²) / (2 r0) + bend x_0², in world units
};

// Leaves around (r0, 0, 0), each a general quadric in the identity frame whose scaled
// coefficients give Q above: with x = c + R y, q(y) = Q(c + R y) / R.
mpu::MpuSurface hand_surface(const std::vector<HandLeaf>& hand) {
  mpu::MpuSurface s;
  s.box_min = Eigen::Vector3d(-2, -12, -12);
  s.box_size = 24;
  s.data_min = Eigen::Vector3d(6, -4, -4);
  s.data_max = Eigen::Vector3d(14, 4, 4);
  for (const HandLeaf& h : hand) {
    mpu::Leaf l;
    l.centre = h.centre;
    l.radius = h.radius;
    l.kind = mpu::FitKind::kGeneralQuadric;
    const Eigen::Vector3d& c = h.centre;
    const double R = h.radius, e = h.bend;
    l.coeffs[0] = (c.squaredNorm() - kR0 * kR0) / (2 * kR0 * R) + e * c.x() * c.x() / R;
    l.coeffs[1] = c.x() / kR0 + 2 * e * c.x();  // u
    l.coeffs[2] = c.y() / kR0;                  // v
    l.coeffs[15] = c.z() / kR0;                 // w
    l.coeffs[3] = R / (2 * kR0) + e * R;        // u²
    l.coeffs[5] = R / (2 * kR0);                // v²
    l.coeffs[16] = R / (2 * kR0);               // w²
    s.leaves.push_back(l);
  }
  mpu::build_lookup_grid(s, 4);
  return s;
}

std::vector<HandLeaf> hand_leaves(double bend) {
  // Different bends per leaf make the leaves disagree, as fits do.
  return {{{10, 0, 0}, 4, 0.0},          {{9, 2, 0}, 3.5, bend},       {{9, -1, 2}, 4.5, -bend},
          {{11, 1, -1}, 3, 2 * bend},    {{8.5, 0, -1.5}, 5, 0.5 * bend}};
}

// Points near (r0, 0, 0) that some leaf holds.
std::vector<Eigen::Vector3d> near_points(const mpu::MpuSurface& s, int count) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-1.5, 1.5);
  std::vector<Eigen::Vector3d> out;
  while (int(out.size()) < count) {
    const Eigen::Vector3d x = Eigen::Vector3d(kR0, 0, 0) + test::random_vector(d, rng);
    if (mpu::evaluate_f(s, x) != s.box_size) out.push_back(x);
  }
  return out;
}

// ∂∇f/∂x_j by central differences of evaluate_fg, step h.
Eigen::Matrix3d gradient_differences(const mpu::MpuSurface& s, const Eigen::Vector3d& x, double h) {
  Eigen::Matrix3d H;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d dx = h * Eigen::Vector3d::Unit(j);
    H.col(j) = (mpu::evaluate_fg(s, x + dx).g - mpu::evaluate_fg(s, x - dx).g) / (2 * h);
  }
  return H;
}

TEST(MpuEval, BlendedHessianIsTheWeightedMeanOfTheLeavesHessians) {
  const std::vector<HandLeaf> hand = hand_leaves(0.02);
  const mpu::MpuSurface s = hand_surface(hand);
  double worst_hb = 0, worst_h = 0, worst_gap = 0;
  for (const Eigen::Vector3d& x : near_points(s, 200)) {
    const mpu::Sample e = mpu::evaluate_hessian(s, x);
    // The definition, from the closed forms: ∇²Q_i = I / r0 + 2 bend_i e0 e0ᵀ.
    double W = 0;
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    for (const HandLeaf& h : hand) {
      double w, dw, d2w;
      mpu::bspline_weight((x - h.centre).norm(), h.radius, w, dw, d2w);
      Eigen::Matrix3d HQ = Eigen::Matrix3d::Identity() / kR0;
      HQ(0, 0) += 2 * h.bend;
      W += w;
      sum += w * HQ;
    }
    ASSERT_GT(W, 0);
    worst_hb = std::max(worst_hb, (e.Hb - sum / W).cwiseAbs().maxCoeff());
    worst_h = std::max(worst_h, (e.H - gradient_differences(s, x, 1e-4)).cwiseAbs().maxCoeff());
    worst_gap = std::max(worst_gap, (e.H - e.Hb).cwiseAbs().maxCoeff());
    // evaluate gives the same f, ∇f and Hb, without H.
    const mpu::Sample c = mpu::evaluate(s, x);
    EXPECT_EQ(c.f, e.f);
    EXPECT_EQ(c.g, e.g);
    EXPECT_EQ(c.Hb, e.Hb);
    EXPECT_EQ(c.H, Eigen::Matrix3d::Zero());
  }
  std::printf("max |Hb - definition| %.2e, max |H - differences of grad f| %.2e, max |H - Hb| %.2e (1/mm)\n",
              worst_hb, worst_h, worst_gap);
  EXPECT_LT(worst_hb, 1e-12);
  EXPECT_LT(worst_h, 1e-6);
  // The leaves disagree, so the Hessian of f carries the weights' derivatives: far from Hb.
  EXPECT_GT(worst_gap, 1e-3);
}

TEST(MpuEval, BothSecondDerivativesAgreeWhereTheLeavesDo) {
  // Every leaf holds the same function: f is that function, and H = Hb = I / r0; on the
  // sphere the curvature is 1 / r0 from either.
  const mpu::MpuSurface s = hand_surface(hand_leaves(0));
  for (const Eigen::Vector3d& x : near_points(s, 50)) {
    const mpu::Sample e = mpu::evaluate_hessian(s, x);
    EXPECT_NEAR(e.f, (x.squaredNorm() - kR0 * kR0) / (2 * kR0), 1e-12);
    EXPECT_LT((e.H - Eigen::Matrix3d::Identity() / kR0).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((e.Hb - Eigen::Matrix3d::Identity() / kR0).cwiseAbs().maxCoeff(), 1e-12);
  }
  const Eigen::Vector3d on(kR0, 0, 0);
  const mpu::Sample e = mpu::evaluate_hessian(s, on);
  for (const mpu::Curvature& c : {mpu::curvature(e), mpu::curvature(e.g, e.H)}) {
    // Convex, outward normal: both principal curvatures -1/r0 (to the square root of the
    // rounding in Kindlmann's discriminant, which vanishes at an umbilic).
    EXPECT_NEAR(c.k1, -1 / kR0, 1e-8);
    EXPECT_NEAR(c.k2, -1 / kR0, 1e-8);
    EXPECT_NEAR(c.gauss, 1 / (kR0 * kR0), 1e-12);
  }
}

TEST(MpuEval, HessianIsTheDerivativeOfTheGradientOnAFittedSphere) {
  const test::AnalyticShape shape{test::AnalyticShape::kSphere, 20, 20, 20};
  const PointCloud cloud = test::sample_shape(shape, 1.0, 1.0, true);
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  std::mt19937 rng(11);
  double worst = 0, scale = 0;
  for (int i = 0; i < 200; ++i) {
    const size_t k = rng() % cloud.size();
    const Eigen::Vector3d x = cloud.positions[k] + 0.3 * std::uniform_real_distribution<double>(-1, 1)(rng) * cloud.normals[k];
    const mpu::Sample e = mpu::evaluate_hessian(s, x);
    worst = std::max(worst, (e.H - gradient_differences(s, x, 1e-4)).cwiseAbs().maxCoeff());
    scale = std::max(scale, e.H.cwiseAbs().maxCoeff());
  }
  std::printf("fitted sphere: max |H - differences of grad f| %.2e, max |H| %.2e (1/mm)\n", worst, scale);
  EXPECT_LT(worst, 1e-5 * scale);
}

}  // namespace
}  // namespace mpumesh
