// Every quality figure on shapes whose answers are known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "mesh/cgal_geometry.h"
#include "mesh/quality.h"
#include "mesh/thin_triangles.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(Quality, RegularIcosahedron) {
  const double a = 2.0;
  const Quality q = measure_quality(test::icosahedron(a));
  EXPECT_EQ(q.topo.vertices, 12);
  EXPECT_EQ(q.topo.triangles, 20);
  EXPECT_EQ(q.topo.edges, 30);
  EXPECT_TRUE(q.topo.closed && q.topo.manifold && q.topo.oriented);
  EXPECT_EQ(q.topo.components, 1);
  EXPECT_EQ(q.topo.euler, 2);
  EXPECT_EQ(q.topo.genus, 0);
  EXPECT_EQ(q.self_intersections, 0);
  EXPECT_NEAR(q.area_mm2, 5.0 * std::sqrt(3.0) * a * a, 1e-9);
  EXPECT_NEAR(q.volume_mm3, 5.0 / 12.0 * (3.0 + std::sqrt(5.0)) * a * a * a, 1e-9);
  EXPECT_NEAR(q.edge_min, a, 1e-12);
  EXPECT_NEAR(q.edge_max, a, 1e-12);
  EXPECT_NEAR(q.angle_min, 60.0, 1e-9);
  EXPECT_NEAR(q.angle_mean, 60.0, 1e-9);
  EXPECT_NEAR(q.radius_ratio_mean, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(q.pct_angle_below[2], 0.0);
  // Dihedral angle of the icosahedron is 138.19 deg; between normals 180 - that.
  EXPECT_NEAR(q.dihedral_mean, 180.0 - std::acos(-std::sqrt(5.0) / 3.0) * 180.0 / std::numbers::pi, 1e-9);
}

TEST(Quality, UnitCube) {
  const Quality q = measure_quality(test::unit_cube());
  EXPECT_TRUE(q.topo.closed && q.topo.manifold && q.topo.oriented);
  EXPECT_EQ(q.topo.genus, 0);
  EXPECT_NEAR(q.area_mm2, 6.0, 1e-12);
  EXPECT_NEAR(q.volume_mm3, 1.0, 1e-12);
  EXPECT_NEAR(q.angle_min, 45.0, 1e-9);
  EXPECT_DOUBLE_EQ(q.pct_angle_below[2], 0.0);
  EXPECT_DOUBLE_EQ(q.pct_angle_below[1], 0.0);
  EXPECT_NEAR(q.radius_ratio_mean, 4.0 / (std::sqrt(2.0) * (2.0 + std::sqrt(2.0))), 1e-12);
  EXPECT_DOUBLE_EQ(q.pct_radius_ratio_below_half, 0.0);
  EXPECT_NEAR(q.dihedral_mean, 60.0, 1e-9);  // 12 edges at 90, 6 diagonals at 0
  EXPECT_NEAR(q.dihedral_p99, 90.0, 1e-9);
  EXPECT_NEAR(q.pct_area_axis_aligned, 100.0, 1e-9);
  EXPECT_NEAR(q.edge_max, std::sqrt(2.0), 1e-12);
}

TEST(Quality, SphereMeshAndDistances) {
  const TriangleMesh s = test::icosphere(10.0, 3);
  TriangleMesh bigger = s;
  for (auto& v : bigger.vertices) v *= 1.02;
  QualityOptions opt;
  opt.reference = &bigger;
  const Quality q = measure_quality(s, opt);
  EXPECT_TRUE(q.topo.closed && q.topo.manifold && q.topo.oriented);
  EXPECT_EQ(q.topo.genus, 0);
  EXPECT_EQ(q.self_intersections, 0);
  EXPECT_NEAR(q.area_mm2, 4 * std::numbers::pi * 100, 0.02 * 1257);
  EXPECT_LT(q.pct_area_axis_aligned, 5.0);
  // Vertices of the smaller sphere are 0.2 mm inside the bigger mesh's vertices; the
  // bigger mesh's flat faces sit a little inside its circumsphere.
  ASSERT_TRUE(q.hausdorff_mm && q.mean_distance_mm);
  EXPECT_NEAR(*q.hausdorff_mm, 0.2, 0.02);
  EXPECT_GT(*q.mean_distance_mm, 0.1);
  EXPECT_LT(*q.mean_distance_mm, 0.2);
  opt.reference = &s;
  const Quality self = measure_quality(s, opt);
  EXPECT_LT(*self.hausdorff_mm, 1e-9);
}

TEST(Quality, OpenMesh) {
  TriangleMesh m = test::icosahedron(1.0);
  m.triangles.pop_back();
  const Quality q = measure_quality(m);
  EXPECT_FALSE(q.topo.closed);
  EXPECT_FALSE(q.topo.manifold);
  EXPECT_EQ(q.topo.border_edges, 3);
  EXPECT_EQ(q.topo.genus, -1);
}

TEST(Quality, NonManifoldEdgeAndVertex) {
  // Three triangles on one edge.
  TriangleMesh fin;
  fin.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_EQ(analyze_topology(fin).nonmanifold_edges, 1);
  // Two closed tetrahedra touching at one vertex: closed, edge-manifold, but the shared
  // vertex has two fans.
  TriangleMesh bow;
  bow.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  bow.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}};
  const Topology t = analyze_topology(bow);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_EQ(t.nonmanifold_vertices, 1);
  EXPECT_FALSE(t.manifold);
}

TEST(Quality, SelfIntersectionsAreCounted) {
  TriangleMesh a = test::icosahedron(2.0), b = test::icosahedron(2.0);
  TriangleMesh both = a;
  for (auto v : b.vertices) both.vertices.push_back(v + Eigen::Vector3d(0.7, 0.1, 0.05));
  for (auto t : b.triangles) both.triangles.push_back({t[0] + 12, t[1] + 12, t[2] + 12});
  const Quality q = measure_quality(both);
  EXPECT_GT(q.self_intersections, 0);
  EXPECT_EQ(q.topo.components, 2);
}

// The pairs found through the box search are those of testing every pair with CGAL's
// exact triangle test: two overlapping spheres of 1,280 triangles each (the box search
// splits sets above 1,000), one vertex of the first pushed through its far side (a fold,
// whose triangles also cross triangles they share a vertex with).
TEST(Quality, IntersectingPairsAreThoseOfTestingEveryPair) {
  const TriangleMesh a = test::icosphere(2.0, 3);
  TriangleMesh both = a;
  const uint32_t n = uint32_t(a.vertices.size());
  for (auto v : a.vertices) both.vertices.push_back(v + Eigen::Vector3d(1.1, 0.3, 0.2));
  for (auto t : a.triangles) both.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  // A fold: one vertex pushed through the sphere's opposite side.
  both.vertices[5] = -1.2 * both.vertices[5];
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto tri = [&](uint32_t f) {
    const auto& t = both.triangles[f];
    auto p = [&](uint32_t v) { return K::Point_3(both.vertices[v].x(), both.vertices[v].y(), both.vertices[v].z()); };
    return K::Triangle_3(p(t[0]), p(t[1]), p(t[2]));
  };
  std::vector<std::pair<uint32_t, uint32_t>> expected;
  for (uint32_t f = 0; f < both.triangles.size(); ++f)
    for (uint32_t g = f + 1; g < both.triangles.size(); ++g) {
      bool share = false;
      for (uint32_t u : both.triangles[f])
        for (uint32_t w : both.triangles[g]) share = share || u == w;
      if (!share && CGAL::do_intersect(tri(f), tri(g))) expected.emplace_back(f, g);
    }
  ASSERT_GT(expected.size(), 100u);
  EXPECT_EQ(intersecting_triangles(both, nullptr, false), expected);
  // Listing some triangles: the pairs that hold one of them, listed few or most.
  for (uint32_t stride : {7u, 1u}) {
    std::vector<uint32_t> among;
    for (uint32_t f = 0; f < both.triangles.size(); f += stride) among.push_back(f);
    std::vector<char> listed(both.triangles.size(), 0);
    for (uint32_t f : among) listed[f] = 1;
    std::vector<std::pair<uint32_t, uint32_t>> want;
    for (const auto& p : expected)
      if (listed[p.first] || listed[p.second]) want.push_back(p);
    EXPECT_EQ(intersecting_triangles(both, &among, false), want) << stride;
  }
  // With adjacent pairs too: the pairs that share no vertex are among them.
  const auto all = intersecting_triangles(both);
  EXPECT_TRUE(std::includes(all.begin(), all.end(), expected.begin(), expected.end()));
}

// The smallest angle from the sides nearest the shortest only is the minimum of all
// three angles, bit for bit: on random triangles, on nearly isosceles and equilateral
// ones (sides equal to 1e-7 to 1e-16), and on degenerate ones.
TEST(Quality, MinAngleIsTheSmallestOfAllThreeBitForBit) {
  auto all_three = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    auto angle = [](const Eigen::Vector3d& u, const Eigen::Vector3d& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); };
    return std::min({angle(b - a, c - a), angle(a - b, c - b), angle(a - c, b - c)}) * (180.0 / std::numbers::pi);
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10, 10);
  auto point = [&] { return test::random_vector(u, rng); };
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d a = point(), b = point();
    Eigen::Vector3d c = point();
    if (i % 2) {  // c on (or within 1e-7 to 1e-16 of) the perpendicular bisector of ab, or equilateral
      const Eigen::Vector3d mid = 0.5 * (a + b), n = (b - a).cross(c - a).normalized(), side = n.cross(b - a);
      const double h = i % 4 == 1 ? std::sqrt(3.0) / 2 : 0.1 + std::abs(u(rng));
      c = mid + h * side + std::pow(10.0, -7 - i % 10) * (b - a);
    }
    EXPECT_EQ(triangle_min_angle_deg(a, b, c), all_three(a, b, c)) << i;
    ++checked;
  }
  const Eigen::Vector3d p(1, 2, 3), q(4, 5, 6);
  EXPECT_EQ(triangle_min_angle_deg(p, p, q), all_three(p, p, q));  // two corners at one point
  EXPECT_EQ(triangle_min_angle_deg(p, q, 0.5 * (p + q)), all_three(p, q, 0.5 * (p + q)));  // collinear
  EXPECT_EQ(triangle_min_angle_deg(p, p, p), all_three(p, p, p));
  EXPECT_EQ(checked, 20000);
}

// The cosine pre-test gives the answer of the angle itself: on random triangles, on
// triangles built with an angle within 1e-9 to 1e-15 degrees of the bound, and on
// degenerate ones.
TEST(Quality, MinAngleBelowAgreesWithTheAngle) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-10, 10);
  auto point = [&] { return test::random_vector(u, rng); };
  int near_bound = 0;
  for (int i = 0; i < 20000; ++i) {
    const double deg = i % 3 == 0 ? 20.0 : i % 3 == 1 ? 25.0 : 30.0;
    const Eigen::Vector3d a = point(), b = point();
    Eigen::Vector3d c = point();
    if (i % 2) {  // the angle at a set to deg, give or take 1e-9 to 1e-15 degrees
      const Eigen::Vector3d e = (b - a).normalized(), n = e.cross(c - a).normalized(), side = n.cross(e);
      const double angle = (deg + (i % 4 == 1 ? 1 : -1) * std::pow(10.0, -9 - i % 7)) * std::numbers::pi / 180;
      c = a + (b - a).norm() * (std::cos(angle) * e + std::sin(angle) * side);  // isosceles: the smallest
      near_bound += std::abs(triangle_min_angle_deg(a, b, c) - deg) < 1e-6;
    }
    EXPECT_EQ(triangle_min_angle_below(a, b, c, deg), triangle_min_angle_deg(a, b, c) < deg) << i;
  }
  EXPECT_GT(near_bound, 5000);
  const Eigen::Vector3d p(1, 2, 3), q(4, 5, 6);
  EXPECT_EQ(triangle_min_angle_below(p, p, q, 30), triangle_min_angle_deg(p, p, q) < 30);
  EXPECT_EQ(triangle_min_angle_below(p, q, 0.5 * (p + q), 30), triangle_min_angle_deg(p, q, 0.5 * (p + q)) < 30);
  EXPECT_EQ(triangle_min_angle_below(p, p, p, 30), triangle_min_angle_deg(p, p, p) < 30);
}

TEST(Quality, TorusGenusOne) {
  // A coarse torus: 8 x 6 quads, each split into two triangles.
  TriangleMesh m;
  const int nu = 8, nv = 6;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      m.vertices.emplace_back((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  auto id = [&](int i, int j) { return uint32_t(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  const Quality q = measure_quality(m);
  EXPECT_TRUE(q.topo.manifold && q.topo.oriented);
  EXPECT_EQ(q.topo.euler, 0);
  EXPECT_EQ(q.topo.genus, 1);
  EXPECT_GT(q.volume_mm3, 0);
  const nlohmann::json j = quality_to_json(q);
  for (const char* key : {"vertices", "triangles", "closed", "manifold", "components", "genus", "self_intersections",
                          "area_mm2", "volume_mm3", "edge_mm", "min_angle_deg", "pct_min_angle_below",
                          "radius_ratio", "dihedral_deg", "pct_area_axis_aligned_5deg", "hausdorff_mm",
                          "mean_distance_mm"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["genus"], 1);
}

}  // namespace
}  // namespace mpumesh
