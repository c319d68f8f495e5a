// The CT-like phantoms' truth (core/phantom) and the figures scored against it: the
// closed forms agree with the shapes' inside tests and with known curvatures, the scan
// puts the half level on the surface, the truth figures of an exact mesh are near zero,
// and the point-noise estimate finds the scatter it is given.
#include <gtest/gtest.h>

#include <random>

#include "mpu/fit_tolerance.h"
#include "phantom/ct_phantom.h"
#include "phantom/truth_figures.h"
#include "points/point_noise.h"
#include "test_support.h"

namespace mpumesh {
namespace {

using phantom::Shape;

TEST(Phantom, ClosestPointsLieOnTheSurfaceWithTheirNormals) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const auto& ph : phantom::suite()) {
    SCOPED_TRACE(ph.name);
    const Shape& s = ph.shape;
    const Eigen::Vector3d half = s.rotation.cwiseAbs() * s.half_extent();
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3d p = s.centre + test::random_vector(u, rng).cwiseProduct(half * 1.2);
      Eigen::Vector3d n;
      const double d = s.distance(p, &n);
      ASSERT_NEAR(n.norm(), 1.0, 1e-9);
      if (d < 0.05) continue;
      // Stepping back along the normal by the distance lands on the surface: just inside
      // and just outside of it lie on either side.
      const Eigen::Vector3d x = s.inside(p) ? Eigen::Vector3d(p + d * n) : Eigen::Vector3d(p - d * n);
      EXPECT_TRUE(s.inside(x - 1e-4 * n)) << p.transpose();
      EXPECT_FALSE(s.inside(x + 1e-4 * n)) << p.transpose();
      ++checked;
    }
    EXPECT_GT(checked, 1000);
  }
}

TEST(Phantom, GaussianCurvatureHasItsKnownValues) {
  Shape e{Shape::kEllipsoid, 30, 21, 15};
  double k;
  e.distance({31, 0, 0}, nullptr, &k);
  EXPECT_NEAR(k, 30.0 * 30 / (21.0 * 21 * 15 * 15), 1e-9);
  EXPECT_NEAR(e.max_abs_gauss(), k, 1e-12);
  e.distance({0, 0, 16}, nullptr, &k);
  EXPECT_NEAR(k, 15.0 * 15 / (30.0 * 30 * 21 * 21), 1e-9);
  const Shape t{Shape::kTorus, 20, 7};
  t.distance({28, 0, 0}, nullptr, &k);
  EXPECT_NEAR(k, 1 / (7.0 * 27), 1e-12);
  t.distance({12, 0, 0}, nullptr, &k);
  EXPECT_NEAR(k, -1 / (7.0 * 13), 1e-12);
  t.distance({20, 0, 8}, nullptr, &k);
  EXPECT_NEAR(k, 0, 1e-12);
  const Shape c{Shape::kCapsule, 10, 15};
  c.distance({11, 0, 5}, nullptr, &k);
  EXPECT_EQ(k, 0);
  EXPECT_FALSE(c.on_cap({11, 0, 5}));
  c.distance({0, 0, 27}, nullptr, &k);
  EXPECT_NEAR(k, 0.01, 1e-12);
  EXPECT_TRUE(c.on_cap({0, 0, 27}));
  const Shape sh{Shape::kShell, 22, 2.5};
  Eigen::Vector3d n;
  EXPECT_NEAR(sh.distance({0, 0, 20}, &n, &k), 0.5, 1e-12);
  EXPECT_NEAR(n.z(), -1, 1e-12);  // the inner sheet's normal points out of the material
  EXPECT_NEAR(k, 1 / (19.5 * 19.5), 1e-12);
}

TEST(Phantom, ScanPutsTheHalfLevelOnTheSurface) {
  phantom::Phantom ph = phantom::suite()[0];
  ph.scan.noise_hu = 0;
  const Volume v = phantom::scan(ph.shape, ph.scan);
  EXPECT_EQ(v.modality, "CT");
  double worst_deep = 0;
  int near = 0, crossing = 0;
  for (int64_t k = 0; k < v.dims[2]; ++k)
    for (int64_t j = 0; j < v.dims[1]; j += 2)
      for (int64_t i = 0; i < v.dims[0]; i += 2) {
        const Eigen::Vector3d p = v.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k)));
        const double d = ph.shape.distance(p);
        const float x = v.at(i, j, k);
        if (d > 2) worst_deep = std::max(worst_deep, std::min(std::abs(x - 1000.0), std::abs(double(x))));
        // A voxel whose centre lies within a tenth of a pixel of a near-vertical wall
        // (partial volume over its box is then about half).
        Eigen::Vector3d n;
        ph.shape.distance(p, &n);
        if (d < 0.06 && std::abs(n.z()) < 0.2) {
          ++near;
          crossing += std::abs(x - 500.0) < 150;
        }
      }
  EXPECT_EQ(worst_deep, 0);  // far from the surface: exactly one level or the other
  ASSERT_GT(near, 20);
  EXPECT_GT(crossing, near * 9 / 10);
}

TEST(TruthFigures, AnExactSphereScoresNearZero) {
  const TriangleMesh m = test::icosphere(20, 5);
  const Shape sphere{Shape::kEllipsoid, 20, 20, 20};
  const phantom::TruthFigures f = phantom::truth_figures(m, sphere);
  EXPECT_LT(f.distance_mean, 1e-6);  // the vertices lie on the sphere
  EXPECT_LT(f.normal_mean_deg, 0.5);  // faces 0.6 mm across on a 20 mm sphere
  EXPECT_FALSE(f.curvature_from_file);
  EXPECT_LT(std::abs(f.gauss_rank), 0.2);  // the true K is constant (to rounding): no ranks
  EXPECT_LT(f.gauss_median_error, 0.05);
}

TEST(PointNoise, FindsTheScatterItIsGiven) {
  const PointCloud clean = test::sample_shape({test::AnalyticShape::kEllipsoid, 30, 21, 15}, 0.5, 0.5, true);
  const double quiet = pts::estimate_noise(clean);
  EXPECT_LT(quiet, 0.01);
  for (double sigma : {0.05, 0.2}) {
    PointCloud noisy = clean;
    std::mt19937 rng(7);
    std::normal_distribution<double> g(0, sigma);
    for (size_t i = 0; i < noisy.size(); ++i) noisy.positions[i] += g(rng) * noisy.normals[i];
    EXPECT_NEAR(pts::estimate_noise(noisy), sigma, 0.25 * sigma) << sigma;
    // The tolerance rule: the in-plane voxel, or 3 sigma when that is larger.
    const mpu::Tolerance t = mpu::volume_tolerance(noisy, 0.4);
    EXPECT_NEAR(t.eps, std::max(0.4, 3 * t.noise), 1e-12);
    EXPECT_FALSE(t.source.empty());
  }
}

}  // namespace
}  // namespace mpumesh
