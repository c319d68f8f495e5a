// core/mpu/local_fit: the local fits of one MPU cell against surfaces they can represent.
#include <gtest/gtest.h>

#include <cmath>

#include "mpu/local_fit.h"

namespace mpumesh::mpu {
namespace {

// Points of z = h(x, y) on a 9 x 9 grid over [-4, 4]², with normals, all in one ball.
template <class H, class G>
PointCloud height_field(H h, G grad, double offset = 0) {
  PointCloud c;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j) {
      const double x = i, y = j;
      c.positions.push_back({x, y, h(x, y) + offset});
      const Eigen::Vector2d g = grad(x, y);
      c.normals.push_back(Eigen::Vector3d(-g.x(), -g.y(), 1).normalized());
    }
  return c;
}

Ball all_of(const PointCloud& c, const Eigen::Vector3d& centre, double radius) {
  Ball b{centre, radius, {}};
  for (uint32_t i = 0; i < c.size(); ++i) b.ids.push_back(i);
  return b;
}

TEST(LocalFit, FrameFromNormalIsRightHandedWithTheNormalLast) {
  for (const Eigen::Vector3d n : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, -1, 0),
                                  Eigen::Vector3d(1, 2, -3).normalized()}) {
    const Eigen::Matrix3d f = frame_from_normal(n);
    EXPECT_LT((f * f.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(f.determinant(), 1.0, 1e-12);
    EXPECT_LT((f.row(2).transpose() - n).norm(), 1e-12);
  }
}

TEST(LocalFit, OrthopolyHeightFieldIsExactOnAQuadricAndRisesForACubic) {
  auto quad = [](double x, double y) { return 0.05 * x * x - 0.03 * x * y + 0.04 * y * y; };
  auto quad_grad = [](double x, double y) { return Eigen::Vector2d(0.1 * x - 0.03 * y, -0.03 * x + 0.08 * y); };
  const PointCloud q = height_field(quad, quad_grad);
  double error = -1;
  const Leaf leaf = fit_height_orthopoly(all_of(q, {0, 0, 0}, 7), q, {0, 0, 1}, 4, 0, &error);
  EXPECT_LT(error, 1e-9);
  EXPECT_EQ(leaf.kind, FitKind::kHeightOrthopoly);
  // Off the fitted points, the leaf is off by their distance: 0.3 mm above the surface.
  const PointCloud above = height_field(quad, quad_grad, 0.3);
  EXPECT_NEAR(taubin_error(leaf, all_of(above, {0, 0, 0}, 7), above), 0.3, 0.02);

  auto cubic = [&](double x, double y) { return quad(x, y) + 0.004 * x * x * x - 0.003 * x * y * y; };
  auto cubic_grad = [&](double x, double y) {
    return Eigen::Vector2d(quad_grad(x, y).x() + 0.012 * x * x - 0.003 * y * y, quad_grad(x, y).y() - 0.006 * x * y);
  };
  const PointCloud c = height_field(cubic, cubic_grad);
  double quadric_error = -1, poly_error = -1;
  fit_height_quadric(all_of(c, {0, 0, 0}, 7), c, {0, 0, 1}, &quadric_error);
  const Leaf cubic_leaf = fit_height_orthopoly(all_of(c, {0, 0, 0}, 7), c, {0, 0, 1}, 4, 0, &poly_error);
  EXPECT_GE(cubic_leaf.degree, 3);
  EXPECT_LT(poly_error, 1e-6);
  EXPECT_GT(quadric_error, 100 * poly_error) << "a quadric cannot follow the cubic term";
  // Capped at degree 2 it is a quadric again.
  double capped_error = -1;
  EXPECT_EQ(fit_height_orthopoly(all_of(c, {0, 0, 0}, 7), c, {0, 0, 1}, 2, 0, &capped_error).degree, 2);
  EXPECT_GT(capped_error, 100 * poly_error);
}

TEST(LocalFit, GeneralQuadricFitsASphereAcrossBothSides) {
  // Points all round a 4 mm sphere (normals disagree: no height field holds them) and, at
  // a cell's corners and centre, the value (|q - c|² - r²) / 2r, which the quadric can
  // match exactly (it is the signed distance to first order at the surface).
  PointCloud c;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 24; ++j) {
      const double t = M_PI * (i + 0.5) / 12, p = 2 * M_PI * j / 24;
      const Eigen::Vector3d n(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      c.positions.push_back(Eigen::Vector3d(1, 2, 3) + 4 * n);
      c.normals.push_back(n);
    }
  std::vector<AuxPoint> aux;
  for (int k = 0; k < 9; ++k) {
    const Eigen::Vector3d q =
        k < 8 ? Eigen::Vector3d(1, 2, 3) + 3 * Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1)
              : Eigen::Vector3d(1, 2, 3);
    aux.push_back({q, ((q - Eigen::Vector3d(1, 2, 3)).squaredNorm() - 16) / 8});
  }
  double error = -1;
  const Leaf leaf = fit_general_quadric(all_of(c, {1, 2, 3}, 6), c, aux, &error);
  EXPECT_EQ(leaf.kind, FitKind::kGeneralQuadric);
  EXPECT_LT(error, 1e-3);
}

TEST(LocalFit, MeanNormalWeighsThePointsNearTheCentre) {
  PointCloud c;
  c.positions = {{0, 0, 0}, {0.9, 0, 0}};
  c.normals = {{0, 0, 1}, {1, 0, 0}};
  const Eigen::Vector3d n = mean_normal(all_of(c, {0, 0, 0}, 1), c);
  EXPECT_GT(n.z(), 10 * n.x()) << "the point at the centre outweighs the one near the rim";
}

}  // namespace
}  // namespace mpumesh::mpu
