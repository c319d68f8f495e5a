// The particle system on fitted analytic shapes: particles on the surface, spacing
// uniform on a sphere and following curvature on an ellipsoid, thin plates respected,
// repeatable runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "mesh/quality.h"
#include "mesh/topology.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/spurious_components.h"
#include "mpu/mpu_fit.h"
#include "particles/data_support.h"
#include "particles/particle_system.h"
#include "particles/spacing_gradation.h"
#include "particles/spacing_stats.h"
#include "test_support.h"

namespace mpumesh {
namespace {

using particles::ParticleState;

// The k-th of n nearly even directions on the unit sphere (a Fibonacci spiral).
Eigen::Vector3d fibonacci_direction(int k, int n) {
  const double z = 1 - (2 * k + 1.0) / n, r = std::sqrt(1 - z * z), phi = k * M_PI * (3 - std::sqrt(5.0));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

struct ShapeRun {
  mpu::MpuSurface surface;
  PointCloud cloud;
  ParticleState st;
  particles::SampleStats stats;
  particles::SpacingStats spacing;
  double max_true_distance = 0;
};

ShapeRun run_shape(const test::AnalyticShape& shape, int64_t count, bool dense = true) {
  ShapeRun r;
  r.cloud = test::sample_shape(shape, 0.5, dense ? 0.5 : 2.0, dense);
  r.surface = mpu::fit_mpu(r.cloud, {});
  particles::SampleOptions o;
  o.particles = count;
  CpuBackend cpu;
  r.st = particles::sample_surface(r.surface, r.cloud.positions, o, cpu, &r.stats);
  std::vector<double> absk;
  for (size_t i = 0; i < r.st.size(); ++i) {
    double K;
    r.max_true_distance = std::max(r.max_true_distance, shape.distance(r.st.x[i], nullptr, &K));
    absk.push_back(std::abs(K));
  }
  r.spacing = particles::spacing_stats(particles::local_spacing(r.st.x), absk);
  return r;
}

void print(const char* name, const ShapeRun& r) {
  std::printf("%s: %lld particles (seeds %lld, pool %lld, births %lld, deaths %lld), %d iterations, converged %d, "
              "h %.3f mm, area %.0f mm2, thickness-bound %lld; spacing mean %.3f cv %.3f, high/low-K %.3f, rank %.3f; "
              "max distance %.2e mm; %.2f s seed, %.2f s iterate, %.2f s population\n",
              name, (long long)r.stats.particles, (long long)r.stats.seeds, (long long)r.stats.pool,
              (long long)r.stats.births, (long long)r.stats.deaths, r.stats.iterations, int(r.stats.converged),
              r.stats.spacing, r.stats.area, (long long)r.stats.thickness_bound, r.spacing.mean, r.spacing.cv,
              r.spacing.ratio, r.spacing.rank_correlation, r.max_true_distance, r.stats.seconds_seed,
              r.stats.seconds_iterate, r.stats.seconds_population);
  for (const auto& h : r.stats.history)
    std::printf("  it %d: %lld (+%lld -%lld) E %.2f move %.4f\n", h.iteration, (long long)h.count, (long long)h.births,
                (long long)h.deaths, h.mean_energy, h.mean_move);
}

TEST(Particles, SphereIsUniform) {
  test::AnalyticShape sphere;
  const ShapeRun r = run_shape(sphere, 3000);
  print("sphere", r);
  EXPECT_LT(r.spacing.cv, 0.15);
  EXPECT_LT(r.max_true_distance, 0.01);
  EXPECT_NEAR(double(r.stats.particles), 3000, 300);
}

TEST(Particles, EllipsoidSpacingFollowsCurvature) {
  test::AnalyticShape e{test::AnalyticShape::kEllipsoid, 30, 20, 10};
  const ShapeRun r = run_shape(e, 4000);
  print("ellipsoid", r);
  EXPECT_LT(r.spacing.ratio, 0.6);
  EXPECT_LT(r.spacing.rank_correlation, -0.5);
  // No plate here: curvature sets every particle's spacing.
  ASSERT_EQ(int64_t(r.stats.spacing_by_thickness.size()), r.stats.particles);
  EXPECT_EQ(std::count(r.stats.spacing_by_thickness.begin(), r.stats.spacing_by_thickness.end(), uint8_t(1)), 0);
}

// The restricted Delaunay mesh of the particles: closed, oriented, the right genus, on
// the true surface, and well-shaped triangles.
void check_mesh(const char* name, const test::AnalyticShape& shape, int64_t count, int64_t genus) {
  const ShapeRun r = run_shape(shape, count);
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

// Targets with a step (0.5 mm for x < 5, 4 mm beyond) on a 0.5 mm grid: graded, they rise
// from the step at the grade, never exceed what they were, and every pair of neighbours
// keeps the bound; along a row the result is the exact distance to the step.
TEST(SpacingGradation, BoundsTheRateOfChange) {
  std::vector<Eigen::Vector3d> x;
  std::vector<double> t;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      x.emplace_back(0.5 * i, 0.5 * j, 0.01 * ((i * 7 + j * 3) % 5));  // a little off the plane
      t.push_back(0.5 * i < 5 ? 0.5 : 4.0);
    }
  std::vector<double> g = t;
  const size_t lowered = particles::limit_spacing_gradient(x, g, 0.3);
  size_t expect_lowered = 0;
  double worst = 0;
  for (size_t a = 0; a < x.size(); ++a) {
    EXPECT_LE(g[a], t[a]);
    if (t[a] == 0.5) EXPECT_EQ(g[a], 0.5);
    expect_lowered += g[a] < t[a];
    for (size_t b = 0; b < x.size(); ++b)
      if ((x[a] - x[b]).norm() < 1.5 * 0.5) worst = std::max(worst, g[a] - g[b] - 0.3 * (x[a] - x[b]).norm());
  }
  EXPECT_EQ(lowered, expect_lowered);
  EXPECT_LE(worst, 1e-12);
  // Along row j = 0 the bound comes from the step's last point in that row (x = 4.5 mm);
  // the grid's path there zigzags a little in z, which may add a few µm.
  const size_t at = 30 * 40;  // i = 30, x = 15 mm
  EXPECT_NEAR(g[at], 0.5 + 0.3 * (x[at] - x[9 * 40]).norm(), 0.015);
  EXPECT_LT(g[at], 4.0);
  EXPECT_EQ(g[39 * 40], 4.0);  // x = 19.5: 0.5 + 0.3 * 15 = 5 > 4, not bound
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
      const Eigen::Vector3d n = fibonacci_direction(k, 400);
      cloud.positions.push_back(Eigen::Vector3d::Constant(c) + 3.0 * n);
      cloud.normals.push_back(n);
    }
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  std::vector<Eigen::Vector3d> outer;
  const int n = 1200;  // about 2 mm apart on r = 20
  for (int k = 0; k < n; ++k) {
    outer.push_back(20.0 * fibonacci_direction(k, n));
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

// The data support: exactly the points within the reach of some candidate are near.
TEST(DataSupport, HoldsThePointsWithinTheReach) {
  std::vector<Eigen::Vector3d> c;
  for (int k = 0; k < 500; ++k) c.push_back(10.0 * fibonacci_direction(k, 500));
  const double reach = 2.0;
  // Cells of the reach (2 mm), and cells of 5 mm (at most 4 along the 20 mm box).
  for (const int max_cells : {128, 4}) {
    const particles::DataSupport ds(c, reach, max_cells);
    int64_t near_tried = 0, near_missed = 0, far_held = 0, far_tried = 0;
    for (int k = 0; k < 20000; ++k) {
      const Eigen::Vector3d q = Eigen::Vector3d(particles::hash01(uint32_t(k), 0, 7, 0),
                                                particles::hash01(uint32_t(k), 0, 7, 1),
                                                particles::hash01(uint32_t(k), 0, 7, 2)) * 32.0 -
                                Eigen::Vector3d::Constant(16);
      double d = INFINITY;
      for (const auto& p : c) d = std::min(d, (p - q).norm());
      (d <= reach ? near_tried : far_tried) += 1;
      (d <= reach ? near_missed : far_held) += d <= reach ? !ds.near(q) : ds.near(q);
    }
    std::printf("reach %.1f mm, at most %d cells a side: %lld of %lld points within it missed, %lld of %lld "
                "farther held\n",
                reach, max_cells, (long long)near_missed, (long long)near_tried, (long long)far_held,
                (long long)far_tried);
    EXPECT_GT(near_tried, 2000);
    EXPECT_GT(far_tried, 5000);
    EXPECT_EQ(near_missed, 0);
    EXPECT_EQ(far_held, 0);
    EXPECT_FALSE(ds.near(Eigen::Vector3d(0, 0, 0)));    // the sphere's centre, 10 mm from all
    EXPECT_FALSE(ds.near(Eigen::Vector3d(100, 0, 0)));  // outside the grid
  }
}

// Particles leave no part of the surface that the candidates do not reach: the union of
// two balls (r = 10 at x = 0 and x = 12) fitted whole, the particles seeded from the
// points with x < 0 only. They spread along the surface towards x = 22; those farther than
// the reach (4 r_pool) from every candidate are removed.
TEST(Particles, StayWithinReachOfTheData) {
  PointCloud cloud, left;
  for (const double cx : {0.0, 12.0})
    for (int k = 0; k < 6000; ++k) {
      const Eigen::Vector3d n = fibonacci_direction(k, 6000);
      const Eigen::Vector3d x = Eigen::Vector3d(cx, 0, 0) + 10.0 * n;
      if ((x - Eigen::Vector3d(12.0 - cx, 0, 0)).norm() < 10) continue;  // inside the other ball
      cloud.positions.push_back(x);
      cloud.normals.push_back(n);
      if (x.x() < 0) left.positions.push_back(x);
    }
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  CpuBackend cpu;
  particles::SampleOptions o;
  o.spacing = 2.0;
  particles::SampleStats st;
  const ParticleState ps = particles::sample_surface(s, left.positions, o, cpu, &st);
  double farthest = 0, right = -INFINITY;
  for (const auto& x : ps.x) {
    double d = INFINITY;
    for (const auto& p : left.positions) d = std::min(d, (p - x).norm());
    farthest = std::max(farthest, d);
    right = std::max(right, x.x());
  }
  std::printf("%lld particles (%lld removed off the data), farthest %.2f mm from the candidates, largest x %.2f mm\n",
              (long long)st.particles, (long long)st.off_data, farthest, right);
  EXPECT_GT(st.off_data, 0);
  EXPECT_GT(right, 0.5);  // they did spread past the candidates
  EXPECT_LT(farthest, 4.0);  // the reach, 4 r_pool, is about 3.6 mm here
}

// Components of a triangle list that hold a sampled vertex: two tetrahedra (vertices 0-3
// and 4-7) and a third joined to the second through vertex 7 (7-10). Only vertex 1 and
// vertex 9 are sampled: the first and the joined pair stay, nothing else is removed. Then
// the components with more than half of their vertices off the sample go too.
TEST(RestrictedDelaunay, KeepsTheComponentsThatParticlesHold) {
  auto tet = [](uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    return std::vector<std::array<uint32_t, 3>>{{a, b, c}, {a, d, b}, {b, d, c}, {a, c, d}};
  };
  std::vector<std::array<uint32_t, 3>> tris;
  for (const auto& t : {tet(0, 1, 2, 3), tet(4, 5, 6, 7), tet(7, 8, 9, 10), tet(11, 12, 13, 14)})
    tris.insert(tris.end(), t.begin(), t.end());
  int64_t unsampled = -1;
  const std::vector<char> keep =
      sampled_components(tris, 15, [](uint32_t v) { return v == 1 || v == 9; }, &unsampled);
  const std::vector<char> want = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0};
  EXPECT_EQ(keep, want);
  EXPECT_EQ(unsampled, 1);
  EXPECT_EQ(std::count(keep.begin(), keep.end(), 1), 12);
  sampled_components(tris, 15, [](uint32_t) { return false; }, &unsampled);
  EXPECT_EQ(unsampled, 3);
  // Off the sample: the first tetrahedron with one of its four vertices off stays (under
  // half); the joined pair, 7 vertices with 4 off (4, 5, 6, 8), goes although vertex 9 is
  // sampled.
  const std::vector<char> keep_off = sampled_components(
      tris, 15, [](uint32_t v) { return v == 1 || v == 9; }, &unsampled,
      [](uint32_t v) { return v == 2 || v == 4 || v == 5 || v == 6 || v == 8; });
  const std::vector<char> want_off = {1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(keep_off, want_off);
  EXPECT_EQ(unsampled, 2);
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
      const Eigen::Vector3d u = fibonacci_direction(k, n);
      cloud.positions.push_back(c + r * u);
      cloud.normals.push_back(u);
    }
    for (int k = 0; particles && k < n / 8; ++k) given.push_back(c + r * fibonacci_direction(k, n / 8));
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

// A thin plate: a spherical shell 1.5 mm thick (outer r 20, inner 18.5), asked for a 4 mm
// spacing. The thickness bound spaces most particles at 1.5 mm, so the restricted
// Delaunay mesh is the two spheres, each closed, no triangle bridges the wall and no
// repair point is needed.
TEST(Particles, ThinPlateIsNotBridged) {
  const PointCloud shell = test::spherical_shell(20, 18.5);
  const mpu::MpuSurface s = mpu::fit_mpu(shell, {});
  CpuBackend cpu;
  for (const double factor : {1.0, 100.0}) {
    particles::SampleOptions o;
    o.spacing = 4.0;
    o.thickness_factor = factor;
    particles::SampleStats st;
    const ParticleState ps = particles::sample_surface(s, shell.positions, o, cpu, &st);
    RestrictedDelaunayStats rs;
    const TriangleMesh m = restricted_delaunay(s, ps.x, &rs);
    int64_t bridging = 0;
    for (const auto& t : m.triangles) {
      int outer = 0;
      for (uint32_t v : t) outer += m.vertices[v].norm() > 19.25;
      bridging += outer == 1 || outer == 2;
    }
    const Topology topo = analyze_topology(m);
    std::printf("thickness factor %g: %lld particles, %lld thickness-bound, %lld repair points, %zu triangles, "
                "%lld bridging, %lld components, closed %d\n",
                factor, (long long)st.particles, (long long)st.thickness_bound, (long long)rs.repair_points,
                m.triangles.size(), (long long)bridging, (long long)topo.components, int(topo.closed));
    // Which bound sets each final particle's spacing: the wall's thickness, with the bound.
    ASSERT_EQ(int64_t(st.spacing_by_thickness.size()), st.particles);
    const int64_t by_wall = std::count(st.spacing_by_thickness.begin(), st.spacing_by_thickness.end(), uint8_t(1));
    if (factor == 1.0) {
      EXPECT_GT(st.thickness_bound, st.particles / 2);
      EXPECT_GT(by_wall, st.particles / 2);
      EXPECT_EQ(bridging, 0);
      EXPECT_EQ(topo.components, 2);
      EXPECT_TRUE(topo.closed);
      EXPECT_EQ(rs.repair_points, 0);
    } else {
      // Without the bound nothing limits the spacing by the wall. (Printed, not asserted:
      // the repulsion across the 1.5 mm wall then drives births and deaths, and the count
      // does not settle; the triangulation still separated the sheets in this case.)
      EXPECT_EQ(st.thickness_bound, 0);
      EXPECT_EQ(by_wall, 0);
    }
  }
}

}  // namespace
}  // namespace mpumesh

namespace mpumesh {
namespace {

// A surface that turns to NaN on one side (as a broken kernel or a corrupt fit would): the
// particle system stops with the iteration and the device named, instead of meshing NaN.
TEST(Particles, NanFromTheSurfaceIsCaughtWithItsIteration) {
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 10, 10, 10};
  const PointCloud cloud = test::sample_shape(sphere, 0.5, 0.5, true);
  mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  for (auto& leaf : s.leaves)
    if (leaf.centre.x() > 6) leaf.coeffs.fill(std::numeric_limits<double>::quiet_NaN());
  CpuBackend cpu;
  const auto rows = cpu.mpu_eval(s, {Eigen::Vector3d(10, 0, 0), Eigen::Vector3d(-10, 0, 0)});
  ASSERT_TRUE(std::isnan(rows[0].f));
  ASSERT_TRUE(std::isfinite(rows[1].f));
  particles::SampleOptions o;
  o.particles = 800;
  try {
    particles::sample_surface(s, cloud.positions, o, cpu);
    FAIL() << "no error";
  } catch (const NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("after iteration"), std::string::npos) << m;
    EXPECT_NE(m.find("CPU"), std::string::npos) << m;
    EXPECT_NE(m.find("nothing was written"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace mpumesh
