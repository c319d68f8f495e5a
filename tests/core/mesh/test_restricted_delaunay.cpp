// The restricted Delaunay triangulation (core/mesh/restricted_delaunay.h): called on a
// fitted sphere and points spread on it, the mesh it makes, that it makes the same one
// each time, and what it refuses; on the particles of fitted shapes, closed meshes of the
// right genus; the manifold repair of a sparse sample, a lost sheet recovered, and a
// sheet between sampled ones meshed and removed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "mesh/quality.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/topology.h"
#include "mpu/mpu_fit.h"
#include "particles/particle_system.h"
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
    for (int k = 0; k < n; ++k) r.points.push_back(r.shape.a * test::fibonacci_direction(k, n));
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

// The restricted Delaunay mesh of the particles: closed, oriented, the right genus, on
// the true surface, and well-shaped triangles.
void check_mesh(const char* name, const test::AnalyticShape& shape, int64_t count, int64_t genus) {
  const test::ShapeRun r = test::run_shape(shape, count);
  RestrictedDelaunayStats rs;
  const TriangleMesh mesh = restricted_delaunay(r.surface, r.st.x, &rs);
  const Quality q = measure_quality(mesh);
  double dmax = 0;
  for (const auto& v : mesh.vertices) dmax = std::max(dmax, shape.distance(v));
  std::printf("%s: %zu particles -> %lld triangles, %lld repair points, %lld unused, %lld flipped, %.2f s; "
              "closed %d oriented %d genus %lld components %lld; self-intersections %lld; min angle %.1f, "
              "p01 %.1f, below 30: %.2f%%, below 20: %.2f%%; radius ratio mean %.3f; dihedral mean %.2f; "
              "vertex distance max %.4f mm\n",
              name, r.st.size(), (long long)q.topo.triangles, (long long)rs.repair_points, (long long)rs.unused_points,
              (long long)rs.flipped_components, rs.seconds, int(q.topo.closed), int(q.topo.oriented),
              (long long)q.topo.genus, (long long)q.topo.components, (long long)q.self_intersections, q.angle_min,
              q.angle_p01, q.pct_angle_below[2], q.pct_angle_below[1], q.radius_ratio_mean, q.dihedral_mean, dmax);
  EXPECT_TRUE(q.topo.closed);
  EXPECT_TRUE(q.topo.oriented);
  EXPECT_EQ(q.topo.components, 1);
  EXPECT_EQ(q.topo.genus, genus);
  EXPECT_EQ(q.self_intersections, 0);
  EXPECT_GT(q.volume_mm3, 0);  // outward
  EXPECT_LT(dmax, 0.01);
}

TEST(RestrictedDelaunay, SphereEllipsoidTorus) {
  check_mesh("sphere", test::AnalyticShape{}, 3000, 0);
  check_mesh("ellipsoid", test::AnalyticShape{test::AnalyticShape::kEllipsoid, 30, 20, 10}, 4000, 0);
  check_mesh("torus", test::AnalyticShape{test::AnalyticShape::kTorus, 25, 8, 8}, 5000, 1);
}

// Points far too sparse for the surface (random input points, a few hundred on a spherical
// shell whose wall is 1.5 mm thick): the restricted Delaunay facets alone are not a
// manifold where a Voronoi cell spans the wall, and the repair adds points on f = 0 until
// they are; the same input gives the same mesh.
TEST(RestrictedDelaunay, RepairsASparseSample) {
  const mpu::MpuSurface s = mpu::fit_mpu(test::spherical_shell(20, 18.5), {});
  const PointCloud cloud = test::spherical_shell(20, 18.5);
  for (const size_t count : {300, 1000, 3000}) {
    std::vector<Eigen::Vector3d> pick;
    uint64_t h = 12345;
    for (size_t k = 0; k < count; ++k) {
      h = h * 6364136223846793005ull + 1442695040888963407ull;
      pick.push_back(cloud.positions[(h >> 33) % cloud.size()]);
    }
    RestrictedDelaunayStats rs;
    const TriangleMesh m = restricted_delaunay(s, pick, &rs);
    const Topology topo = analyze_topology(m);
    double dmax = 0;
    for (const auto& v : m.vertices) dmax = std::max(dmax, std::min(std::abs(v.norm() - 20), std::abs(v.norm() - 18.5)));
    // The closest two vertices: a repair crossing next to one inserted just before it
    // (the same missing point) is left out, not made a vertex microns from the other.
    double closest = INFINITY;
    for (size_t a = 0; a < m.vertices.size(); ++a)
      for (size_t b = a + 1; b < m.vertices.size(); ++b) closest = std::min(closest, (m.vertices[a] - m.vertices[b]).norm());
    std::printf("%zu random points: %lld repair points in %lld rounds (%lld crossings merged), %lld unused, %zu "
                "triangles, closed %d oriented %d genus %lld components %lld, vertices within %.4f mm, closest two "
                "%.4f mm\n",
                count, (long long)rs.repair_points, (long long)rs.repair_rounds, (long long)rs.repair_merged,
                (long long)rs.unused_points, m.triangles.size(), int(topo.closed), int(topo.oriented),
                (long long)topo.genus, (long long)topo.components, dmax, closest);
    EXPECT_GT(rs.repair_points, 0);
    EXPECT_GT(rs.repair_merged, 0);
    EXPECT_TRUE(topo.closed);
    EXPECT_TRUE(topo.manifold);
    EXPECT_TRUE(topo.oriented);
    EXPECT_LT(dmax, 0.02);
    const TriangleMesh again = restricted_delaunay(s, pick);
    EXPECT_EQ(again.vertices, m.vertices);
    EXPECT_EQ(again.triangles, m.triangles);
    // With too small a budget of repair points it says so, rather than going on.
    try {
      restricted_delaunay(s, pick, nullptr, rs.repair_points / 2);
      ADD_FAILURE() << "no error";
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("too sparse"), std::string::npos) << e.what();
    }
  }
}

// A plate that a particle's Voronoi cell holds whole: a spherical shell 0.6 mm thick
// (outer r 20, inner 19.4) with particles on its outer sheet only, 2 mm apart. Every
// Voronoi edge there crosses the wall twice or not at all, so no facet is restricted and
// the whole shell would drop out of the mesh; the lost-sheet repair puts points on the
// inner sheet, and the mesh is both spheres, closed. (Two small balls fitted with the
// shell, at (±36, ±36, ±36), keep the data's box away from it: the repair leaves alone
// what lies within a reach of the box, where a CT volume cuts the anatomy.)
TEST(RestrictedDelaunay, RecoversASheetThatVoronoiCellsHoldWhole) {
  PointCloud cloud = test::spherical_shell(20, 19.4);
  for (const double c : {-36.0, 36.0})
    for (int k = 0; k < 400; ++k) {
      const Eigen::Vector3d n = test::fibonacci_direction(k, 400);
      cloud.positions.push_back(Eigen::Vector3d::Constant(c) + 3.0 * n);
      cloud.normals.push_back(n);
    }
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  std::vector<Eigen::Vector3d> outer;
  const int n = 1200;  // about 2 mm apart on r = 20
  for (int k = 0; k < n; ++k) {
    outer.push_back(20.0 * test::fibonacci_direction(k, n));
  }
  RestrictedDelaunayStats rs;
  const TriangleMesh m = restricted_delaunay(s, outer, &rs);
  const Topology topo = analyze_topology(m);
  double dmax = 0;
  int64_t inner = 0;
  for (const auto& v : m.vertices) {
    dmax = std::max(dmax, std::min(std::abs(v.norm() - 20), std::abs(v.norm() - 19.4)));
    inner += v.norm() < 19.7;
  }
  std::printf("outer sheet only: %lld sheet points, %lld repair points, %lld unused, %zu triangles, %lld vertices "
              "inside, components %lld, closed %d, vertices within %.4f mm\n",
              (long long)rs.sheet_points, (long long)rs.repair_points, (long long)rs.unused_points,
              m.triangles.size(), (long long)inner, (long long)topo.components, int(topo.closed), dmax);
  EXPECT_GT(rs.sheet_points, 0);
  EXPECT_GT(inner, n / 4);
  EXPECT_LT(rs.unused_points, n / 20);
  EXPECT_TRUE(topo.closed);
  EXPECT_TRUE(topo.manifold);
  EXPECT_TRUE(topo.oriented);
  EXPECT_EQ(topo.components, 2);
  EXPECT_LT(dmax, 0.15);  // the fit of a 0.6 mm wall lies within 0.1 mm of the spheres
}

// A sheet of f that no particle samples between two that particles do: three balls fitted
// (r = 10 at x = ±20, r = 3 at the origin) and particles on the two large ones only, about
// 1.6 mm apart. Delaunay cells that bridge the 20 mm gap have their circumcentres in the
// small ball, where f < 0: without the wide-facet refinement their facets made a tube
// from one sphere to the other, closed and manifold (one component of 1,988 triangles).
// The refinement samples the small ball with repair points; that component holds no
// particle and is removed. Left: the two spheres, closed, nothing near the small ball.
TEST(RestrictedDelaunay, SamplesASheetBetweenSampledOnes) {
  PointCloud cloud;
  std::vector<Eigen::Vector3d> given;
  auto sphere = [&](const Eigen::Vector3d& c, double r, int n, bool particles) {
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d u = test::fibonacci_direction(k, n);
      cloud.positions.push_back(c + r * u);
      cloud.normals.push_back(u);
    }
    for (int k = 0; particles && k < n / 8; ++k) given.push_back(c + r * test::fibonacci_direction(k, n / 8));
  };
  sphere({-20, 0, 0}, 10, 4000, true);
  sphere({20, 0, 0}, 10, 4000, true);
  sphere({0, 0, 0}, 3, 400, false);
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  RestrictedDelaunayStats rs;
  const TriangleMesh m = restricted_delaunay(s, given, &rs);
  const Topology topo = analyze_topology(m);
  double nearest = INFINITY;  // the closest vertex to the small ball's centre
  for (const auto& v : m.vertices) nearest = std::min(nearest, v.norm());
  std::printf("%zu particles: %lld wide facets refined, %lld repair points, %lld components (%lld triangles) "
              "removed; %zu triangles, %lld components, closed %d, nearest vertex %.2f mm from the small ball's "
              "centre\n",
              given.size(), (long long)rs.wide_facets, (long long)rs.repair_points, (long long)rs.spurious_components,
              (long long)rs.spurious_triangles, m.triangles.size(), (long long)topo.components, int(topo.closed),
              nearest);
  EXPECT_GT(rs.wide_facets, 0);
  EXPECT_GE(rs.spurious_components, 1);
  EXPECT_EQ(topo.components, 2);
  EXPECT_TRUE(topo.closed);
  EXPECT_TRUE(topo.manifold);
  EXPECT_GT(nearest, 9.5);  // only the large spheres, 10 mm from the centre at their nearest
}

}  // namespace
}  // namespace mpumesh
