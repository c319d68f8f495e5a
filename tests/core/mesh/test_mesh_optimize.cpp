// core/mesh/mesh_optimize: the restricted Delaunay mesh of uneven points on a fitted
// ellipsoid, optimised: better shaped (no triangle under 25°), still closed, oriented and of the same genus,
// every vertex still on f = 0, no triangles crossing, and the same each time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cpu/cpu_backend.h"
#include "geometry/tet_mesh.h"
#include "mesh/cgal_geometry.h"
#include "mesh/mesh_optimize.h"
#include "mesh/quality.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/topology.h"
#include "mpu/mpu_eval_ref.h"
#include "mpu/mpu_fit.h"
#include "particles/particle_step_ref.h"
#include "test_support.h"

namespace mpumesh {
namespace {

struct Case {
  test::AnalyticShape shape{test::AnalyticShape::kEllipsoid, 24, 16, 12};
  mpu::MpuSurface surface;
  TriangleMesh mesh;  // of jittered points: many poor triangles
  std::vector<double> spacing;
};

// A torus (radii 16 and 5 mm) meshed coarsely: a jittered 40 x 12 grid of its angles, so
// that about 30° lies between neighbouring triangles around the tube.
Case make_torus() {
  Case r;
  r.shape = {test::AnalyticShape::kTorus, 16, 5, 5};
  r.surface = mpu::fit_mpu(test::sample_shape(r.shape, 0.4, 0.4, true), {});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  std::vector<Eigen::Vector3d> points;
  const int nu = 40, nv = 12;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * (i + jitter(rng)) / nu, v = 2 * M_PI * (j + jitter(rng)) / nv;
      Eigen::Vector3d p((16 + 5 * std::cos(v)) * std::cos(u), (16 + 5 * std::cos(v)) * std::sin(u), 5 * std::sin(v));
      particles::newton_project(r.surface, p, 8, 5.0);
      points.push_back(p);
    }
  r.mesh = restricted_delaunay(r.surface, points);
  r.spacing.assign(r.mesh.vertices.size(), 2.6);
  return r;
}

const Case& ellipsoid() {
  static const Case c = [] {
    Case r;
    r.surface = mpu::fit_mpu(test::sample_shape(r.shape, 0.5, 0.5, true), {});
    std::mt19937 rng(5);
    std::normal_distribution<double> jitter(0, 0.02);
    std::vector<Eigen::Vector3d> points;
    const int n = 2500;
    for (int k = 0; k < n; ++k) {  // a Fibonacci spiral on the sphere, jittered, onto the ellipsoid
      const Eigen::Vector3d d = test::fibonacci_direction(k, n);
      Eigen::Vector3d u = d + test::random_vector(jitter, rng);
      u.normalize();
      Eigen::Vector3d p(r.shape.a * u.x(), r.shape.b * u.y(), r.shape.c * u.z());
      particles::newton_project(r.surface, p, 8, 5.0);
      points.push_back(p);
    }
    r.mesh = restricted_delaunay(r.surface, points);
    double sum = 0;
    int edges = 0;
    for (const auto& t : r.mesh.triangles)
      for (int e = 0; e < 3; ++e, ++edges) sum += (r.mesh.vertices[t[size_t(e)]] - r.mesh.vertices[t[size_t((e + 1) % 3)]]).norm();
    r.spacing.assign(r.mesh.vertices.size(), sum / edges);
    return r;
  }();
  return c;
}

TEST(MeshOptimize, MakesBetterTrianglesOnTheSameClosedSurface) {
  const Case& c = ellipsoid();
  TriangleMesh m = c.mesh;
  CpuBackend cpu;
  const OptimizeStats st = optimize_mesh(m, c.surface, cpu, c.spacing);
  std::printf("before: smallest %.2f deg, %.2f%% under 30, radius ratio %.4f; after: %.2f, %.2f%%, %.4f; %lld flips, "
              "%lld collapses, %lld moves, %.3f s\n",
              st.before.min_angle_deg, st.before.pct_below_30, st.before.radius_ratio, st.after.min_angle_deg,
              st.after.pct_below_30, st.after.radius_ratio, (long long)st.flips, (long long)st.collapses, (long long)st.moves, st.seconds);
  EXPECT_EQ(st.rounds, OptimizeOptions{}.rounds);
  EXPECT_GT(st.flips, 0);
  EXPECT_GT(st.before.pct_below_30, 5.0);  // the jittered points' mesh is poor
  EXPECT_LT(st.after.pct_below_30, st.before.pct_below_30 / 5);
  EXPECT_GT(st.after.radius_ratio, st.before.radius_ratio + 0.02);
  EXPECT_GE(st.after.min_angle_deg, 25.0);
  const ShapeFigures now = shape_figures(m);
  EXPECT_DOUBLE_EQ(now.radius_ratio, st.after.radius_ratio);
  // The same surface: closed, oriented, one sphere, on f = 0, nothing crossing; each
  // collapse removed one vertex and two triangles.
  ASSERT_EQ(m.vertices.size() + size_t(st.collapses), c.mesh.vertices.size());
  ASSERT_EQ(m.triangles.size() + 2 * size_t(st.collapses), c.mesh.triangles.size());
  const Topology t = analyze_topology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.nonmanifold_edges + t.nonmanifold_vertices, 0);
  EXPECT_EQ(count_self_intersections(m), 0);
  double worst = 0;
  for (const auto& v : m.vertices) worst = std::max(worst, std::abs(mpu::evaluate_f(c.surface, v)));
  EXPECT_LT(worst, 1e-6);
  // Repeatable.
  TriangleMesh again = c.mesh;
  optimize_mesh(again, c.surface, cpu, c.spacing);
  EXPECT_EQ(again.vertices, m.vertices);
  EXPECT_EQ(again.triangles, m.triangles);
}

TEST(MeshOptimize, KeepsTheSizesItIsGiven) {
  // Half the spacing on one side of the plane x = 0: the relaxation draws vertices to that
  // side (the density weights), where uniform weights would keep them even.
  const Case& c = ellipsoid();
  TriangleMesh m = c.mesh;
  std::vector<double> spacing = c.spacing;
  for (size_t v = 0; v < spacing.size(); ++v)
    if (m.vertices[v].x() > 0) spacing[v] *= 0.5;
  CpuBackend cpu;
  auto share_right = [](const TriangleMesh& mesh) {
    double right = 0;
    for (const auto& v : mesh.vertices) right += v.x() > 0;
    return right / double(mesh.vertices.size());
  };
  TriangleMesh even = c.mesh;
  optimize_mesh(even, c.surface, cpu, c.spacing);
  optimize_mesh(m, c.surface, cpu, spacing);
  // Vertices drift toward the dense side (0.502 before, 0.502 with even sizes, 0.515).
  std::printf("share of the vertices at x > 0: before %.3f, even sizes %.3f, denser there %.3f\n", share_right(c.mesh),
              share_right(even), share_right(m));
  EXPECT_GT(share_right(m), share_right(even) + 0.01);
}

TEST(MeshOptimize, FlipsEdgesToASmootherSurface) {
  // The coarse torus optimised without and with step 5: a lower mean dihedral angle, at
  // the cost of little radius ratio, and still closed and crossing nothing.
  const Case c = make_torus();
  CpuBackend cpu;
  OptimizeOptions without;
  without.smooth_flip_rounds = 0;
  TriangleMesh m0 = c.mesh, m1 = c.mesh;
  const OptimizeStats s0 = optimize_mesh(m0, c.surface, cpu, c.spacing, without);
  const OptimizeStats s1 = optimize_mesh(m1, c.surface, cpu, c.spacing);
  QualityOptions q;
  q.self_intersections = false;
  const Quality q0 = measure_quality(m0, q), q1 = measure_quality(m1, q);
  std::printf("mean dihedral %.3f -> %.3f deg, radius ratio %.4f -> %.4f, smallest angle %.2f -> %.2f, %lld flips\n",
              q0.dihedral_mean, q1.dihedral_mean, s0.after.radius_ratio, s1.after.radius_ratio, s0.after.min_angle_deg,
              s1.after.min_angle_deg, (long long)s1.smooth_flips);
  EXPECT_EQ(s0.smooth_flips, 0);
  EXPECT_GT(s1.smooth_flips, 0);
  EXPECT_LT(q1.dihedral_mean, q0.dihedral_mean - 0.05);
  EXPECT_GT(s1.after.radius_ratio, s0.after.radius_ratio - 0.005);
  EXPECT_GE(s1.after.min_angle_deg, 25.0);
  const Topology t = analyze_topology(m1);
  EXPECT_TRUE(t.closed && t.oriented);
  EXPECT_EQ(t.genus, 1);
  EXPECT_EQ(t.nonmanifold_edges + t.nonmanifold_vertices, 0);
  EXPECT_EQ(count_self_intersections(m1), 0);
}

// The vertices of three triangles whose tetrahedron with their neighbours is flat (a
// dihedral angle under 15°).
int64_t flat_caps(const TriangleMesh& m) {
  std::vector<std::vector<uint32_t>> ring(m.vertices.size());
  for (const auto& t : m.triangles)
    for (uint32_t v : t)
      for (uint32_t w : t)
        if (w != v && std::find(ring[v].begin(), ring[v].end(), w) == ring[v].end()) ring[v].push_back(w);
  int64_t n = 0;
  for (size_t v = 0; v < ring.size(); ++v) {
    if (ring[v].size() != 3) continue;
    const auto a = dihedral_angles(m.vertices[v], m.vertices[ring[v][0]], m.vertices[ring[v][1]], m.vertices[ring[v][2]]);
    n += *std::min_element(a.begin(), a.end()) < 15;
  }
  return n;
}

TEST(MeshOptimize, RemovesFlatVerticesOfThreeTriangles) {
  // Ten of the mesh's best triangles split at their centroids on f = 0: each new vertex sits
  // a hair above the triangle of its neighbours, and a volume mesh would need that flat
  // tetrahedron. The optimisation removes them; told not to (flat_cap_deg 0), it keeps them.
  const Case& c = ellipsoid();
  TriangleMesh split = c.mesh;
  std::vector<double> spacing = c.spacing;
  std::vector<std::pair<double, uint32_t>> best;
  for (uint32_t f = 0; f < split.triangles.size(); ++f) {
    const auto& t = split.triangles[f];
    best.push_back({-triangle_min_angle_deg(split.vertices[t[0]], split.vertices[t[1]], split.vertices[t[2]]), f});
  }
  std::sort(best.begin(), best.end());
  for (int k = 0; k < 10; ++k) {
    const auto t = split.triangles[best[size_t(k) * 50].second];  // apart from each other
    Eigen::Vector3d p = (split.vertices[t[0]] + split.vertices[t[1]] + split.vertices[t[2]]) / 3;
    particles::newton_project(c.surface, p, 8, 1.0);
    const uint32_t v = uint32_t(split.vertices.size());
    split.vertices.push_back(p);
    spacing.push_back(c.spacing[0]);
    split.triangles[best[size_t(k) * 50].second] = {t[0], t[1], v};
    split.triangles.push_back({t[1], t[2], v});
    split.triangles.push_back({t[2], t[0], v});
  }
  ASSERT_EQ(flat_caps(split), flat_caps(c.mesh) + 10);
  CpuBackend cpu;
  // Here, on a smooth surface, a round's flips and collapses take them too; without those
  // (as at the tip of a knife-edge rim on the sample CT, where no two triangles are
  // coplanar enough to flip), the removal alone.
  TriangleMesh kept = split, removed = split;
  OptimizeOptions remove, keep;
  remove.min_keep_deg = keep.min_keep_deg = 10;
  remove.max_flip_dihedral_deg = keep.max_flip_dihedral_deg = 0;
  keep.flat_cap_deg = 0;
  optimize_mesh(kept, c.surface, cpu, spacing, keep);
  const OptimizeStats st = optimize_mesh(removed, c.surface, cpu, spacing, remove);
  std::printf("flat vertices of three triangles: %lld (10 made), %lld left without their removal, %lld with\n",
              (long long)flat_caps(split), (long long)flat_caps(kept), (long long)flat_caps(removed));
  EXPECT_GT(flat_caps(kept), 0);
  EXPECT_EQ(flat_caps(removed), 0);
  EXPECT_EQ(removed.vertices.size() + size_t(st.collapses), split.vertices.size());
  const Topology t = analyze_topology(removed);
  EXPECT_TRUE(t.closed && t.oriented);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(count_self_intersections(removed), 0);
}

TEST(MeshOptimize, PolishesASpeckOfFourVertices) {
  // A 2 mm sphere meshed by a lopsided tetrahedron (a speck of bone that caught four
  // particles): no edge can collapse and the centroids alone leave it poor; the polishing
  // moves make it nearly regular, on f = 0.
  const test::AnalyticShape shape{test::AnalyticShape::kSphere, 2, 2, 2};
  const mpu::MpuSurface surface = mpu::fit_mpu(test::sample_shape(shape, 0.1, 0.1, true), {});
  TriangleMesh speck;
  const double z = -2.0 / 3, rho = std::sqrt(4 - z * z);
  speck.vertices = {{0, 0, 2}};
  for (double deg : {0.0, 25.0, 200.0})
    speck.vertices.push_back({rho * std::cos(deg * M_PI / 180), rho * std::sin(deg * M_PI / 180), z});
  speck.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  for (auto& v : speck.vertices) particles::newton_project(surface, v, 8, 1.0);
  const std::vector<double> spacing(4, 3.0);
  CpuBackend cpu;
  TriangleMesh unpolished = speck, polished = speck;
  OptimizeOptions none;
  none.polish_passes = 0;
  const OptimizeStats a = optimize_mesh(unpolished, surface, cpu, spacing, none);
  const OptimizeStats b = optimize_mesh(polished, surface, cpu, spacing);
  std::printf("smallest angle: %.2f deg before, %.2f without polishing, %.2f with (%lld polishing moves)\n",
              a.before.min_angle_deg, a.after.min_angle_deg, b.after.min_angle_deg, (long long)b.polish_moves);
  EXPECT_LT(a.after.min_angle_deg, 25.0);
  EXPECT_GT(b.polish_moves, 0);
  EXPECT_GE(b.after.min_angle_deg, 25.0);
  EXPECT_EQ(polished.triangles, speck.triangles);
  EXPECT_TRUE(analyze_topology(polished).oriented);
  for (const auto& v : polished.vertices) EXPECT_LT(std::abs(mpu::evaluate_f(surface, v)), 1e-6);
}

}  // namespace
}  // namespace mpumesh
