// core/mesh/restricted_delaunay called directly, on a fitted sphere and points spread on
// it: the mesh it makes, that it makes the same one each time, and what it refuses. (The
// particle system's meshes of other shapes, the repair and the sheets are tested with the
// particles, in test_particles.cpp.)
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_circumcenter_traits_3.h>

#include <cmath>
#include <random>

#include "common/error.h"
#include "mesh/circumcentre.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/topology.h"
#include "mpu/mpu_fit.h"
#include "test_support.h"

namespace mpumesh {
namespace {

struct Sphere {
  test::AnalyticShape shape;  // radius 20 about the origin
  mpu::MpuSurface surface;
  std::vector<Eigen::Vector3d> points;  // n nearly even points on the true sphere
};

const Sphere& sphere() {
  static const Sphere s = [] {
    Sphere r;
    r.surface = mpu::fit_mpu(test::sample_shape(r.shape, 0.5, 0.5, true), {});
    const int n = 3000;
    for (int k = 0; k < n; ++k) {  // a Fibonacci spiral
      const double z = 1 - (2 * k + 1.0) / n, rho = std::sqrt(1 - z * z), phi = k * M_PI * (3 - std::sqrt(5.0));
      r.points.push_back(r.shape.a * Eigen::Vector3d(rho * std::cos(phi), rho * std::sin(phi), z));
    }
    return r;
  }();
  return s;
}

TEST(RestrictedDelaunay, MeshesEvenPointsOnASphereClosedOutwardAndOnTheSurface) {
  const Sphere& s = sphere();
  RestrictedDelaunayStats st;
  const TriangleMesh m = restricted_delaunay(s.surface, s.points, &st);
  const Topology t = analyze_topology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(st.particles, int64_t(s.points.size()));
  EXPECT_EQ(st.repair_points, 0) << "an even sample this dense needs no repair";
  EXPECT_EQ(st.unused_points, 0);
  EXPECT_EQ(m.vertices.size(), s.points.size());
  EXPECT_NEAR(double(m.triangles.size()), 2.0 * double(s.points.size()) - 4, 0.5);  // Euler, genus 0
  for (const auto& v : m.vertices) EXPECT_NEAR(v.norm(), s.shape.a, 0.05);
  for (const auto& f : m.triangles) {
    const Eigen::Vector3d a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
    EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0) << "a triangle faces inward";
  }
}

TEST(RestrictedDelaunay, MakesTheSameMeshEachTimeWhateverTheOrderOfThePoints) {
  const Sphere& s = sphere();
  const TriangleMesh a = restricted_delaunay(s.surface, s.points);
  const TriangleMesh b = restricted_delaunay(s.surface, s.points);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  // Reversed, the points keep their ids' roles: the same triangles between the same
  // positions, the ids mapped.
  std::vector<Eigen::Vector3d> reversed(s.points.rbegin(), s.points.rend());
  const TriangleMesh c = restricted_delaunay(s.surface, reversed);
  EXPECT_EQ(c.triangles.size(), a.triangles.size());
  auto sorted_faces = [](const TriangleMesh& m) {
    std::vector<std::array<double, 9>> faces;
    for (auto f : m.triangles) {
      std::rotate(f.begin(), std::min_element(f.begin(), f.end(), [&](uint32_t x, uint32_t y) {
                    return std::lexicographical_compare(m.vertices[x].data(), m.vertices[x].data() + 3,
                                                        m.vertices[y].data(), m.vertices[y].data() + 3);
                  }),
                  f.end());
      std::array<double, 9> row;
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) row[size_t(3 * k + d)] = m.vertices[f[size_t(k)]][d];
      faces.push_back(row);
    }
    std::sort(faces.begin(), faces.end());
    return faces;
  };
  EXPECT_EQ(sorted_faces(c), sorted_faces(a));
}

TEST(RestrictedDelaunay, RefusesFewerThanFourPoints) {
  const Sphere& s = sphere();
  const std::vector<Eigen::Vector3d> three(s.points.begin(), s.points.begin() + 3);
  EXPECT_THROW(restricted_delaunay(s.surface, three), InputError);
}


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
  auto point = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
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
