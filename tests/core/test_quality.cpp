// Every quality figure on shapes whose answers are known.
#include <gtest/gtest.h>

#include <numbers>

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
