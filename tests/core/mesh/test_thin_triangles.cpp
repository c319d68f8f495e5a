// core/mesh/thin_triangles: the cleanup of needles next to repair points, on a sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mesh/quality.h"
#include "mesh/thin_triangles.h"
#include "mesh/topology.h"
#include "test_support.h"

namespace mpumesh {
namespace {

double smallest_angle_deg(const TriangleMesh& m) {
  double worst = 180;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = m.vertices[t[size_t(k)]], b = m.vertices[t[size_t((k + 1) % 3)]],
                            c = m.vertices[t[size_t((k + 2) % 3)]];
      worst = std::min(worst, std::acos(std::clamp((b - a).normalized().dot((c - a).normalized()), -1.0, 1.0)) * 180 /
                                  M_PI);
    }
  return worst;
}

// The icosphere with its first edge split at a point 2% of the way from one end, on the
// sphere: two needles beside that short edge, the new vertex last (as a repair point).
TriangleMesh with_needles(TriangleMesh m, double r) {
  const uint32_t a = m.triangles[0][0], b = m.triangles[0][1];
  const uint32_t p = uint32_t(m.vertices.size());
  m.vertices.push_back((0.98 * m.vertices[a] + 0.02 * m.vertices[b]).normalized() * r);
  std::vector<std::array<uint32_t, 3>> out;
  for (const auto& t : m.triangles) {
    int e = -1;
    for (int k = 0; k < 3; ++k)
      if ((t[size_t(k)] == a && t[size_t((k + 1) % 3)] == b) || (t[size_t(k)] == b && t[size_t((k + 1) % 3)] == a)) e = k;
    if (e < 0) {
      out.push_back(t);
      continue;
    }
    const uint32_t u = t[size_t(e)], v = t[size_t((e + 1) % 3)], w = t[size_t((e + 2) % 3)];
    out.push_back({u, p, w});
    out.push_back({p, v, w});
  }
  m.triangles = out;
  return m;
}

TEST(ThinTriangles, CollapsesTheNeedlesOfARepairPointAndKeepsTheSphereClosed) {
  const double r = 10;
  const TriangleMesh sphere = test::icosphere(r, 3);
  TriangleMesh m = with_needles(sphere, r);
  ASSERT_LT(smallest_angle_deg(m), 5);
  const ThinTriangleStats st =
      remove_thin_triangles(m, [&](const Eigen::Vector3d& x) { return std::abs(x.norm() - r); });
  EXPECT_GE(st.collapses, 1);
  EXPECT_EQ(m.triangles.size(), sphere.triangles.size());
  EXPECT_EQ(m.vertices.size(), sphere.vertices.size());
  EXPECT_EQ(st.kept.size(), m.vertices.size());
  EXPECT_GE(smallest_angle_deg(m), smallest_angle_deg(sphere) - 1e-9);
  const Topology t = analyze_topology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, 0);
}

TEST(ThinTriangles, LeavesFrozenVerticesAlone) {
  const double r = 10;
  TriangleMesh m = with_needles(test::icosphere(r, 3), r);
  const size_t triangles = m.triangles.size();
  FrozenVertices frozen(m.vertices.size());
  frozen.freeze(uint32_t(m.vertices.size() - 1));  // the repair point
  for (const auto& t : m.triangles)
    if (std::find(t.begin(), t.end(), uint32_t(m.vertices.size() - 1)) != t.end())
      for (uint32_t v : t) frozen.freeze(v);
  ThinTriangleOptions opt;
  opt.frozen = frozen;
  const ThinTriangleStats st =
      remove_thin_triangles(m, [&](const Eigen::Vector3d& x) { return std::abs(x.norm() - r); }, opt);
  EXPECT_EQ(st.collapses, 0);
  EXPECT_EQ(m.triangles.size(), triangles);
}

TEST(ThinTriangles, RelaxationMovesACrowdedVertexBackAndStaysOnTheSurface) {
  const double r = 10;
  TriangleMesh m = test::icosphere(r, 3);
  // One vertex slid most of the way toward a neighbour, along the sphere.
  const uint32_t v = m.triangles[0][0], w = m.triangles[0][1];
  m.vertices[v] = (0.15 * m.vertices[v] + 0.85 * m.vertices[w]).normalized() * r;
  const double crowded = smallest_angle_deg(m);
  ASSERT_LT(crowded, 15);
  const std::vector<uint32_t> moved =
      relax_thin_triangles(m, [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(x.normalized() * r); });
  EXPECT_FALSE(moved.empty());
  EXPECT_GT(smallest_angle_deg(m), crowded + 10);
  for (const auto& x : m.vertices) EXPECT_NEAR(x.norm(), r, 1e-9);
}

// A needle made by a point inserted next to a vertex of a closed mesh (as a triangulation
// repair point can be) is collapsed away; the mesh stays closed, oriented and genus 0.
TEST(ThinTriangles, NeedleNextToAVertexIsCollapsed) {
  TriangleMesh m = test::icosphere(10.0, 3);
  const Quality before = measure_quality(m, {});
  const size_t nv = m.vertices.size();
  // Split triangle 0 at a point 0.05 of the way from its first corner to its centroid.
  const auto t = m.triangles[0];
  const Eigen::Vector3d c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3;
  const Eigen::Vector3d p = (m.vertices[t[0]] + 0.05 * (c - m.vertices[t[0]])).normalized() * 10.0;
  m.vertices.push_back(p);
  const uint32_t q = uint32_t(nv);
  m.triangles[0] = {t[0], t[1], q};
  m.triangles.push_back({t[1], t[2], q});
  m.triangles.push_back({t[2], t[0], q});
  ASSERT_LT(measure_quality(m, {}).angle_min, 5.0);
  const auto on_sphere = [](const Eigen::Vector3d& x) { return std::abs(x.norm() - 10.0); };
  {
    // With a vertex of the needle frozen, nothing around it changes.
    TriangleMesh frozen_mesh = m;
    FrozenVertices frozen(m.vertices.size());
    frozen.freeze(t[2]);
    ThinTriangleOptions o;
    o.frozen = frozen;
    const ThinTriangleStats fs = remove_thin_triangles(frozen_mesh, on_sphere, o);
    EXPECT_EQ(fs.collapses, 0);
    EXPECT_EQ(frozen_mesh.triangles.size(), m.triangles.size());
    EXPECT_EQ(fs.kept.size(), m.vertices.size());
  }
  const ThinTriangleStats st = remove_thin_triangles(m, on_sphere);
  const Quality after = measure_quality(m, {});
  EXPECT_EQ(st.collapses, 1);
  EXPECT_EQ(m.vertices.size(), nv);
  EXPECT_TRUE(after.topo.closed);
  EXPECT_TRUE(after.topo.oriented);
  EXPECT_EQ(after.topo.genus, 0);
  EXPECT_NEAR(after.angle_min, before.angle_min, 1e-9);
  EXPECT_GT(after.volume_mm3, 0);
}

// A vertex pushed most of the way to a neighbour leaves thin triangles around it that no
// collapse can take (its edges are not short against the others'); relaxing moves it
// back toward its ring's centre, on the surface, with the triangles as they were.
TEST(ThinTriangles, RelaxationMendsAPushedVertex) {
  TriangleMesh m = test::icosphere(10.0, 3);
  const auto t = m.triangles[0];
  const uint32_t v = t[0];
  m.vertices[v] = (m.vertices[v] + 0.85 * (m.vertices[t[1]] - m.vertices[v])).normalized() * 10.0;
  ASSERT_LT(measure_quality(m, {}).angle_min, 10.0);
  const auto project = [](const Eigen::Vector3d& x) { return Eigen::Vector3d(x.normalized() * 10.0); };
  {
    // With every vertex frozen, nothing moves.
    TriangleMesh still = m;
    FrozenVertices frozen(m.vertices.size());
    for (uint32_t v = 0; v < m.vertices.size(); ++v) frozen.freeze(v);
    RelaxOptions o;
    o.frozen = frozen;
    EXPECT_TRUE(relax_thin_triangles(still, project, o).empty());
    EXPECT_EQ(still.vertices, m.vertices);
  }
  const auto triangles = m.triangles;
  const std::vector<uint32_t> moved = relax_thin_triangles(m, project);
  const Quality after = measure_quality(m, {});
  EXPECT_TRUE(std::find(moved.begin(), moved.end(), v) != moved.end());
  EXPECT_GE(after.angle_min, 20.0);
  EXPECT_EQ(m.triangles, triangles);
  EXPECT_TRUE(after.topo.closed);
  EXPECT_EQ(after.topo.genus, 0);
  for (const auto& x : m.vertices) EXPECT_NEAR(x.norm(), 10.0, 1e-9);
}

}  // namespace
}  // namespace mpumesh
