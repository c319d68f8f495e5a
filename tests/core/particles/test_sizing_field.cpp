// core/particles/sizing_field: curvature averaged over each point's patch (the sampling's
// scale), kept apart across a plate's two faces, and the field the particles read their
// targets from.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "particles/sizing_field.h"
#include "test_support.h"

namespace mpumesh::particles {
namespace {

// A 21 x 21 grid of 0.5 mm on the plane z = z0 with normal (0, 0, side).
void add_plane(double z0, double side, std::vector<Eigen::Vector3d>& x, std::vector<Eigen::Vector3d>& n) {
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) {
      x.push_back({0.5 * i, 0.5 * j, z0});
      n.push_back({0, 0, side});
    }
}

TEST(SizingField, PatchMeansCutTheNoiseAndKeepTheLevel) {
  std::vector<Eigen::Vector3d> x, n;
  add_plane(0, 1, x, n);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.01);
  std::vector<double> gauss(x.size()), kappa(x.size()), area(x.size(), 0.25), radius(x.size(), 2.0);
  for (size_t i = 0; i < x.size(); ++i) gauss[i] = 0.02 + noise(rng), kappa[i] = 0.1 + noise(rng);
  auto sd = [](const std::vector<double>& v, double mean) {
    double s = 0;
    for (double a : v) s += (a - mean) * (a - mean);
    return std::sqrt(s / double(v.size()));
  };
  const double before = sd(gauss, 0.02);
  average_over_patches(x, n, area, radius, gauss, kappa);
  // A patch of radius 2 mm holds about 50 points: the noise falls by about 7.
  EXPECT_LT(sd(gauss, 0.02), before / 4);
  EXPECT_LT(sd(kappa, 0.1), before / 4);
  double mean = 0;
  for (double g : gauss) mean += g / double(gauss.size());
  EXPECT_NEAR(mean, 0.02, 0.002);
}

TEST(SizingField, APlatesTwoFacesDoNotMix) {
  // Faces 0.5 mm apart, facing away from each other, with different curvatures: a patch
  // of 2 mm reaches across, but the normals keep the faces apart.
  std::vector<Eigen::Vector3d> x, n;
  add_plane(0.5, 1, x, n);
  const size_t top = x.size();
  add_plane(0, -1, x, n);
  std::vector<double> gauss(x.size()), kappa(x.size()), area(x.size(), 0.25), radius(x.size(), 2.0);
  for (size_t i = 0; i < x.size(); ++i) gauss[i] = i < top ? 0.01 : 0.05, kappa[i] = i < top ? 0.1 : 0.3;
  average_over_patches(x, n, area, radius, gauss, kappa);
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(gauss[i], i < top ? 0.01 : 0.05, 1e-12) << i;
    EXPECT_NEAR(kappa[i], i < top ? 0.1 : 0.3, 1e-12) << i;
  }
  // The field reads the face whose normal agrees with the query's.
  std::vector<double> value(x.size());
  for (size_t i = 0; i < x.size(); ++i) value[i] = i < top ? 1.0 : 2.0;
  const SizingField field(x, n, value);
  EXPECT_DOUBLE_EQ(field.at({0.1, 0.2, 0.48}, {0, 0, 1}), 1.0);
  EXPECT_DOUBLE_EQ(field.at({0.1, 0.2, 0.02}, {0, 0, -1}), 2.0);
}

TEST(SizingField, InterpolatesBetweenItsPoints) {
  std::vector<Eigen::Vector3d> x, n;
  add_plane(0, 1, x, n);
  std::vector<double> value(x.size());
  for (size_t i = 0; i < x.size(); ++i) value[i] = 1 + 0.1 * x[i].x();  // linear in x
  const SizingField field(x, n, value);
  EXPECT_NEAR(field.at({0.5, 0.5, 0}, {0, 0, 1}), 1.05, 1e-9);  // on a point
  // Between points, a mean of the values around: within a grid step's change of the line.
  EXPECT_NEAR(field.at({0.25, 0.25, 0}, {0, 0, 1}), 1.025, 0.01);
}

// Two fields over the same points and tree read from one search: each value is the one
// its own field gives, bit for bit, at random places and normals.
TEST(SizingField, TwoFieldsFromOneSearchGiveTheirOwnValues) {
  std::vector<Eigen::Vector3d> x, n;
  add_plane(0.5, 1, x, n);
  add_plane(0, -1, x, n);
  std::vector<double> a(x.size()), b(x.size());
  for (size_t i = 0; i < x.size(); ++i) a[i] = 1 + 0.1 * x[i].x() + 0.3 * x[i].z(), b[i] = std::sin(double(i));
  const PointIndex index(x);
  const SizingField fa(x, n, a, &index.tree), fb(x, n, b, &index.tree);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 3);
  for (int k = 0; k < 500; ++k) {
    Eigen::Vector3d p = test::random_vector(u, rng);
    p.z() *= 0.25;
    const Eigen::Vector3d nq = test::random_vector(u, rng).normalized();
    const auto [va, vb] = fa.at_with(fb, p, nq);
    EXPECT_EQ(va, fa.at(p, nq)) << k;
    EXPECT_EQ(vb, fb.at(p, nq)) << k;
  }
}

}  // namespace
}  // namespace mpumesh::particles
