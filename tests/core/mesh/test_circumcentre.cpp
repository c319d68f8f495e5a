// The robust circumcentre, bit for bit as CGAL's Robust_circumcenter_traits_3 makes it.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_circumcenter_traits_3.h>
#include <cmath>
#include <random>

#include "mesh/circumcentre.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// The interval shortcut gives CGAL's robust circumcentre bit for bit: on well-shaped
// tetrahedra, on nearly flat ones (the fourth point 1e-9 to 1e-15 mm off the others'
// circle, where the lazy kernel's intervals may not suffice), and on flat ones.
TEST(Circumcentre, SameBitsAsCgalsRobustConstruction) {
  using K = CGAL::Robust_circumcenter_traits_3<CGAL::Epick>;
  auto robust = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d) {
    auto in = [](const Eigen::Vector3d& p) { return K::Point_3(p.x(), p.y(), p.z()); };
    const K::Point_3 x = K().construct_circumcenter_3_object()(in(a), in(b), in(c), in(d));
    return Eigen::Vector3d(x.x(), x.y(), x.z());
  };
  auto same = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
    for (int k = 0; k < 3; ++k)
      if (!(x[k] == y[k] || (std::isnan(x[k]) && std::isnan(y[k])))) return false;
    return true;
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-50, 50);
  auto point = [&] { return test::random_vector(u, rng); };
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d a = point(), b = point(), c = point(), d = point();
    EXPECT_TRUE(same(robust_circumcentre(a, b, c, d), robust(a, b, c, d))) << i;
    ++checked;
  }
  for (int i = 0; i < 2000; ++i) {
    // Four points on one circle (in a tilted plane), the last moved off it by eps.
    const Eigen::Vector3d centre = point(), n = Eigen::Vector3d(point()).normalized();
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const double r = 1 + std::abs(u(rng)) / 10, eps = std::pow(10.0, -9 - i % 7);
    auto on = [&](double t) { return Eigen::Vector3d(centre + r * (std::cos(t) * e1 + std::sin(t) * e2)); };
    const Eigen::Vector3d a = on(0.1 * i), b = on(0.1 * i + 2), c = on(0.1 * i + 4), d = on(0.1 * i + 5) + eps * n;
    EXPECT_TRUE(same(robust_circumcentre(a, b, c, d), robust(a, b, c, d))) << i;
    const Eigen::Vector3d flat = on(0.1 * i + 5);  // exactly (to rounding) on the circle
    EXPECT_TRUE(same(robust_circumcentre(a, b, c, flat), robust(a, b, c, flat))) << i;
    checked += 2;
  }
  EXPECT_EQ(checked, 24000);
}

}  // namespace
}  // namespace mpumesh
