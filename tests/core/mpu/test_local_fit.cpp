// core/mpu/local_fit: the local fits of one MPU cell against surfaces they can represent.
#include <gtest/gtest.h>

#include <cmath>

#include "mpu/local_fit.h"
#include "mpu/mpu_eval_ref.h"

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

// Points of the spheres of radius r_up (normals along +r when up_out, else -r) and r_down
// (the other way) over a 9 x 9 grid of x, y in [-3, 3]: near the pole, two sheets about
// 2 mm apart.
PointCloud two_spheres(double r_up, double r_down, bool plate) {
  PointCloud c;
  for (double r : {r_up, r_down})
    for (int i = -4; i <= 4; ++i)
      for (int j = -4; j <= 4; ++j) {
        const Eigen::Vector3d p(0.75 * i, 0.75 * j, std::sqrt(r * r - 0.5625 * (i * i + j * j)));
        const bool out = (r == r_up) == plate;  // a plate's outer sheet faces out, its inner one in
        c.positions.push_back(p);
        c.normals.push_back((out ? 1.0 : -1.0) * p.normalized());
      }
  return c;
}

// The leaf's Q, ∇Q and Hessian in world units at x (local_poly.h: Q = R q).
struct WorldValue {
  double Q;
  Eigen::Vector3d g;
  Eigen::Matrix3d H;
};
WorldValue at(const Leaf& l, const Eigen::Vector3d& x) {
  const Eigen::Vector3d y = l.frame * (x - l.centre) / l.radius;
  double q, g[3], h[6];
  local_poly(l.coeffs.data(), y.x(), y.y(), y.z(), q, g, h);
  Eigen::Matrix3d Hq;
  Hq << h[0], h[1], h[2], h[1], h[3], h[4], h[2], h[4], h[5];
  return {l.radius * q, l.frame.transpose() * Eigen::Vector3d(g[0], g[1], g[2]),
          l.frame.transpose() * Hq * l.frame / l.radius};
}

TEST(LocalFit, TwoSheetsHoldBothFacesOfACurvedPlate) {
  const PointCloud c = two_spheres(20, 18, true);
  double error = -1;
  const Leaf leaf = fit_two_sheets(all_of(c, {0, 0, 19}, 4), c, &error);
  EXPECT_EQ(leaf.kind, FitKind::kTwoSheets);
  EXPECT_LT(error, 0.01);  // a quadric holds a 20 mm sphere over ±3 mm to about 1 µm
  EXPECT_LT(at(leaf, {0, 0, 19}).Q, 0);  // the plate between the sheets is inside
  EXPECT_GT(at(leaf, {0, 0, 21}).Q, 0);
  EXPECT_GT(at(leaf, {0, 0, 17}).Q, 0);
  for (const auto& [x, r] : {std::pair{Eigen::Vector3d(0.5, -0.3, 0), 20.0}, std::pair{Eigen::Vector3d(0.5, -0.3, 0), 18.0}}) {
    Eigen::Vector3d p = x;
    p.z() = std::sqrt(r * r - x.squaredNorm());
    const WorldValue v = at(leaf, p);
    const Eigen::Vector3d outward = (r == 20 ? 1.0 : -1.0) * p.normalized();
    EXPECT_NEAR(v.Q, 0, 0.01) << r;
    EXPECT_NEAR(v.g.norm(), 1, 0.05) << r;  // about a signed distance
    EXPECT_GT(v.g.normalized().dot(outward), std::cos(0.1 * M_PI / 180)) << r;
    // Each sheet's curvature is its sphere's: K = 1 / r².
    EXPECT_NEAR(curvature(v.g, v.H).gauss * r * r, 1, 0.03) << r;
  }
}

TEST(LocalFit, TwoSheetsOfAGapAreOutsideBetween) {
  const PointCloud c = two_spheres(20, 18, false);
  double error = -1;
  const Leaf leaf = fit_two_sheets(all_of(c, {0, 0, 19}, 4), c, &error);
  EXPECT_LT(error, 0.01);
  EXPECT_GT(at(leaf, {0, 0, 19}).Q, 0);
  EXPECT_LT(at(leaf, {0, 0, 21}).Q, 0);
  EXPECT_LT(at(leaf, {0, 0, 17}).Q, 0);
}

TEST(LocalFit, TwoSheetsRefuseOneSheetAndSheetsThatCross) {
  double error = 0;
  auto quad = [](double x, double y) { return 0.05 * x * x + 0.04 * y * y; };
  auto quad_grad = [](double x, double y) { return Eigen::Vector2d(0.1 * x, 0.08 * y); };
  const PointCloud one = height_field(quad, quad_grad);
  fit_two_sheets(all_of(one, {0, 0, 0}, 7), one, &error);
  EXPECT_TRUE(std::isinf(error));
  // z = 0.3 x facing up and z = -0.3 x facing down: they cross along x = 0.
  PointCloud cross = height_field([](double x, double) { return 0.3 * x; }, [](double, double) { return Eigen::Vector2d(0.3, 0); });
  const PointCloud down = height_field([](double x, double) { return -0.3 * x; }, [](double, double) { return Eigen::Vector2d(-0.3, 0); });
  for (size_t i = 0; i < down.size(); ++i) {
    cross.positions.push_back(down.positions[i]);
    cross.normals.push_back(-down.normals[i]);
  }
  fit_two_sheets(all_of(cross, {0, 0, 0}, 7), cross, &error);
  EXPECT_TRUE(std::isinf(error));
}

}  // namespace
}  // namespace mpumesh::mpu
