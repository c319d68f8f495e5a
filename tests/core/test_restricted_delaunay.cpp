// core/mesh/restricted_delaunay called directly, on a fitted sphere and points spread on
// it: the mesh it makes, that it makes the same one each time, and what it refuses. (The
// particle system's meshes of other shapes, the repair and the sheets are tested with the
// particles, in test_particles.cpp.)
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
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

}  // namespace
}  // namespace mpumesh
