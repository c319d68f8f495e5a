// The MPU surface against analytic shapes sampled as oriented points (dense-uniform and as
// slice stacks at 0.5 mm in-plane, 2 mm between slices): f at the true surface, normals,
// Gaussian curvature, and no zero crossing far from the true surface; and the paper's
// orthogonal-polynomial fit against Ohtake's quadric on the slice-stacked ellipsoid.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "common/neighbour_grid.h"
#include "cpu/cpu_backend.h"
#include "io/volume_io.h"
#include "mpu/mpu_eval_ref.h"
#include "mpu/mpu_fit.h"
#include "points/slice_points.h"
#include "segment/segmentation.h"
#include "test_support.h"

namespace mpumesh {
namespace {

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[size_t(q * double(v.size() - 1))];
}

struct Accuracy {
  double f_p95 = 0, f_max = 0, normal_p95_deg = 0, normal_max_deg = 0, gauss_rel_p95 = 0;
  double worst_sheet_mm = 0;  // farthest zero crossing from the true surface
  int64_t leaves = 0;
  int64_t crossings = 0;  // grid edges where f changes sign
};

Accuracy measure(const test::AnalyticShape& shape, const mpu::MpuSurface& s) {
  Accuracy a;
  a.leaves = int64_t(s.leaves.size());
  // True surface points: a dense sample on a grid offset from the fitted one.
  const PointCloud truth = test::sample_shape(shape, 0.71, 0.71, true);
  std::vector<double> f, ang, kr;
  const double K_scale = shape.kind == test::AnalyticShape::kTorus ? 1.0 / (shape.b * (shape.a + shape.b)) : 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const auto e = mpu::evaluate(s, truth.positions[i]);
    const auto c = mpu::curvature(e);
    Eigen::Vector3d n;
    double K;
    shape.distance(truth.positions[i], &n, &K);
    f.push_back(std::abs(e.f));
    ang.push_back(std::acos(std::clamp(e.g.normalized().dot(n), -1.0, 1.0)) * 180 / M_PI);
    // Relative to |K|, or to the torus's largest |K| where K passes through zero.
    kr.push_back(std::abs(c.gauss - K) / std::max(std::abs(K), 0.2 * K_scale));
  }
  a.f_p95 = percentile(f, 0.95);
  a.f_max = percentile(f, 1.0);
  a.normal_p95_deg = percentile(ang, 0.95);
  a.normal_max_deg = percentile(ang, 1.0);
  a.gauss_rel_p95 = percentile(kr, 0.95);
  // Spurious sheets: sign changes of f along grid edges over the whole cube, located by
  // linear interpolation, measured against the true surface.
  const int n = 96;
  const double step = s.box_size / n;
  std::vector<double> grid(size_t((n + 1) * (n + 1) * (n + 1)));
  auto at = [&](int i, int j, int k) { return Eigen::Vector3d(s.box_min + step * Eigen::Vector3d(double(i), double(j), double(k))); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) grid[size_t(i + (n + 1) * (j + (n + 1) * k))] = mpu::evaluate(s, at(i, j, k)).f;
  auto val = [&](int i, int j, int k) { return grid[size_t(i + (n + 1) * (j + (n + 1) * k))]; };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        for (int d = 0; d < 3; ++d) {
          const int i2 = i + (d == 0), j2 = j + (d == 1), k2 = k + (d == 2);
          if (i2 > n || j2 > n || k2 > n) continue;
          const double f0 = val(i, j, k), f1 = val(i2, j2, k2);
          if ((f0 < 0) == (f1 < 0)) continue;
          const double t = f0 / (f0 - f1);
          const Eigen::Vector3d p = at(i, j, k) + t * (at(i2, j2, k2) - at(i, j, k));
          a.worst_sheet_mm = std::max(a.worst_sheet_mm, shape.distance(p));
          ++a.crossings;
        }
  return a;
}

struct Case {
  const char* name;
  test::AnalyticShape shape;
  bool dense;
};

class MpuShapes : public ::testing::TestWithParam<Case> {};

TEST_P(MpuShapes, FitsTheTrueSurface) {
  const Case& c = GetParam();
  const double h_xy = 0.5, h_z = c.dense ? 0.5 : 2.0;
  const PointCloud cloud = test::sample_shape(c.shape, h_xy, h_z, c.dense);
  // The orthopoly fit (the default), Ohtake's quadric, and the orthopoly fit that fits the
  // (here exact) normals too.
  enum Variant { kOrtho, kQuadric, kOrthoNormals };
  std::map<Variant, Accuracy> by_kind;
  for (Variant variant : {kOrtho, kQuadric, kOrthoNormals}) {
    mpu::FitOptions opt;
    opt.local_fit = variant == kQuadric ? mpu::LocalFit::kQuadric : mpu::LocalFit::kOrthopoly;
    opt.fit_normals = variant == kOrthoNormals;
    const char* name = variant == kOrtho ? "orthopoly" : variant == kQuadric ? "quadric" : "orthopoly+normals";
    mpu::FitStats st;
    const mpu::MpuSurface s = mpu::fit_mpu(cloud, opt, &st);
    const Accuracy a = measure(c.shape, s);
    by_kind[variant] = a;
    std::printf(
        "[ %s %s ] %zu points, %lld leaves (%lld general quadrics, degrees 2/3/4: %lld/%lld/%lld, %lld over eps "
        "%.3f), %.2f s; |f| p95 %.4f max %.4f mm; normal p95 %.2f max %.2f deg; K rel p95 %.3f; %lld crossings, "
        "farthest %.3f mm\n",
        c.name, name, cloud.size(), (long long)st.leaves, (long long)st.general_quadric,
        (long long)st.degree_counts[2], (long long)st.degree_counts[3], (long long)st.degree_counts[4],
        (long long)st.over_eps, st.eps, st.seconds, a.f_p95, a.f_max, a.normal_p95_deg, a.normal_max_deg,
        a.gauss_rel_p95, (long long)a.crossings, a.worst_sheet_mm);
    EXPECT_GT(a.crossings, 1000);
    // No zero crossing farther than two slice spacings from the true surface.
    EXPECT_LE(a.worst_sheet_mm, 2 * h_z) << name;
    if (variant == kQuadric) continue;
    // |f| at the true surface within 1% of the sampling spacing (of the slice spacing for
    // a stack), normals within 2°.
    EXPECT_LE(a.f_max, 0.01 * h_z) << name;
    EXPECT_LE(a.normal_max_deg, 2.0) << name;
    // K (from the blended Hessian, mpu_eval_ref.h) within 5% over 95% of the surface for
    // every shape but the sliced ellipsoid (measured: sphere 2.4% dense, 2.3% sliced;
    // ellipsoid 3.0% dense; torus, whose K changes sign, 3.6% dense and sliced against
    // 0.2 x its largest |K|). The sliced ellipsoid reaches 6.2%, at its rim: there the
    // radius of curvature across the slices is 3.3 mm (10² / 30), under two slice
    // spacings, and only ten slices cross its 20 mm thickness; bounded at 7%. Fitting the
    // normals too, it reaches 5.5% (bounded at 6%): the slopes across the slices pin the
    // height field between the contours; the others stay within 0.1% of the default's.
    // (With the Hessian of f instead, whose weight derivatives carry the leaves'
    // disagreement, these were 1.9 / 2.2 / 3.4 / 5.8 / 5.5%, and 11.3% and 7.0% sliced.)
    double k_bound = 0.05;
    if (c.shape.kind == test::AnalyticShape::kEllipsoid && !c.dense) k_bound = variant == kOrthoNormals ? 0.06 : 0.07;
    EXPECT_LE(a.gauss_rel_p95, k_bound) << name;
  }
  if (c.shape.kind == test::AnalyticShape::kEllipsoid && !c.dense) {
    // The orthogonal-polynomial fit is no worse than the quadric: distance of f = 0 to the
    // true surface (|f| there, p95 and max) and the farthest zero crossing.
    const Accuracy& o = by_kind[kOrtho];
    const Accuracy& q = by_kind[kQuadric];
    EXPECT_LE(o.f_p95, q.f_p95);
    EXPECT_LE(o.f_max, q.f_max);
    EXPECT_LE(o.worst_sheet_mm, q.worst_sheet_mm);
    // And the normals' slopes make the sliced ellipsoid's K better (5.5% against 6.2%;
    // with the Hessian of f, 7.0% against 11.3%: that Hessian's blending error was most of
    // what they mended).
    EXPECT_LT(by_kind[kOrthoNormals].gauss_rel_p95, 0.95 * o.gauss_rel_p95);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Analytic, MpuShapes,
    ::testing::Values(Case{"sphere_dense", {test::AnalyticShape::kSphere, 20, 20, 20}, true},
                      Case{"sphere_slices", {test::AnalyticShape::kSphere, 20, 20, 20}, false},
                      Case{"ellipsoid_dense", {test::AnalyticShape::kEllipsoid, 30, 20, 10}, true},
                      Case{"ellipsoid_slices", {test::AnalyticShape::kEllipsoid, 30, 20, 10}, false},
                      Case{"torus_dense", {test::AnalyticShape::kTorus, 25, 8, 8}, true},
                      Case{"torus_slices", {test::AnalyticShape::kTorus, 25, 8, 8}, false}),
    [](const auto& info) { return std::string(info.param.name); });


// Where the children's balls would be held at the smallest radius, a cell splits only above
// 2 eps. A dense sphere (r 20 mm, 0.5 mm) with Gaussian noise of 0.1 mm along the normals,
// eps 0.3 mm (3 sigma), smallest radius 2.5 mm: the level-4 cells' balls (3.6 mm) are free,
// their children's (1.8 mm) would be held, and the largest error over a level-4 ball's
// 150-odd points is about its noise's 3 sigma, so some of those cells are over eps and
// within 2 eps. They stay leaves (measured: 550 of 2,598 leaves), and the surface stays
// within half the noise of the sphere (|f| p95 0.031 mm, normals' p95 1.96 degrees).
TEST(MpuFit, CellsWhoseChildrenWouldBeHeldSplitOnlyAboveTwiceEps) {
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 20, 20, 20};
  PointCloud cloud = test::sample_shape(sphere, 0.5, 0.5, true);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  for (size_t i = 0; i < cloud.size(); ++i) cloud.positions[i] += noise(rng) * cloud.normals[i];
  mpu::FitOptions opt;
  opt.eps = 0.3;
  opt.min_radius = 2.5;
  mpu::FitStats st;
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, opt, &st);
  const Accuracy a = measure(sphere, s);
  std::printf("%lld leaves, %lld over eps, %lld kept within 2 eps; |f| p95 %.4f max %.4f mm, normal p95 %.2f deg\n",
              (long long)st.leaves, (long long)st.over_eps, (long long)st.kept_below_held_bound, a.f_p95, a.f_max,
              a.normal_p95_deg);
  EXPECT_GT(st.kept_below_held_bound, 0);
  EXPECT_LE(st.kept_below_held_bound, st.over_eps);
  EXPECT_LE(a.f_p95, 0.05);
  EXPECT_LE(a.normal_p95_deg, 3.0);
}

// The sample CT (bone at 226 HU, 0.96 x 0.96 x 1.5 mm): the orthopoly fit is no worse than
// Ohtake's quadric in |f| at the input points (the surface's distance to them) and in
// spurious sheets, zero crossings of f on a grid farther than two slice spacings from
// every input point.
TEST(MpuSampleCt, OrthopolyNoWorseThanQuadric) {
  MPUMESH_DATA_OR_SKIP(path, test::sample_ct_path(), "invesalius-examples");
  const Volume vol = read_volume(path);
  CpuBackend cpu;
  seg::SegmentOptions so;
  so.method = seg::Method::kThreshold;
  so.threshold = {226};
  const PointCloud cloud = pts::extract_points(seg::segment(vol, so, cpu), vol).cloud;
  const double far = 2 * vol.spacing.z();
  const NeighbourGrid near(cloud.positions, far);
  struct Figures {
    double f_p50, f_p95;
    int64_t crossings = 0, sheets = 0;
  };
  std::map<mpu::LocalFit, Figures> by_kind;
  for (auto kind : {mpu::LocalFit::kOrthopoly, mpu::LocalFit::kQuadric}) {
    mpu::FitOptions opt;
    opt.local_fit = kind;
    mpu::FitStats st;
    const mpu::MpuSurface s = mpu::fit_mpu(cloud, opt, &st);
    Figures fig;
    std::vector<double> f;
    for (const auto& r : cpu.mpu_eval(s, cloud.positions)) f.push_back(std::abs(r.f));
    fig.f_p50 = percentile(f, 0.5);
    fig.f_p95 = percentile(f, 0.95);
    // Grid of 1.5 mm over the points' box.
    const double h = 1.5;
    const Eigen::Vector3d lo = s.data_min - Eigen::Vector3d::Constant(2 * h);
    std::array<int, 3> n;
    for (int d = 0; d < 3; ++d) n[size_t(d)] = int(std::ceil((s.data_max[d] - s.data_min[d]) / h)) + 5;
    auto at = [&](int i, int j, int k) { return Eigen::Vector3d(lo + h * Eigen::Vector3d(double(i), double(j), double(k))); };
    std::vector<double> g(size_t(n[0]) * size_t(n[1]) * size_t(n[2]));
    auto idx = [&](int i, int j, int k) { return size_t(i) + size_t(n[0]) * (size_t(j) + size_t(n[1]) * size_t(k)); };
    tbb::parallel_for(0, n[2], [&](int k) {
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) g[idx(i, j, k)] = mpu::evaluate_f(s, at(i, j, k));
    });
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i + 1 < n[0]; ++i) {
          const double f0 = g[idx(i, j, k)], f1 = g[idx(i + 1, j, k)];
          if ((f0 < 0) == (f1 < 0)) continue;
          ++fig.crossings;
          const Eigen::Vector3d p = at(i, j, k) + Eigen::Vector3d(h * f0 / (f0 - f1), 0, 0);
          bool close = false;
          near.for_each_within(p, [&](uint32_t) { close = true; });
          fig.sheets += !close;
        }
    std::printf("[ sample CT %s ] %zu points, %lld leaves, %.2f s; |f| at the points p50 %.4f p95 %.4f mm; %lld "
                "crossings on x edges, %lld farther than %.1f mm from every point\n",
                mpu::local_fit_name(kind), cloud.size(), (long long)st.leaves, st.seconds, fig.f_p50, fig.f_p95,
                (long long)fig.crossings, (long long)fig.sheets, far);
    by_kind[kind] = fig;
  }
  const Figures& o = by_kind[mpu::LocalFit::kOrthopoly];
  const Figures& q = by_kind[mpu::LocalFit::kQuadric];
  EXPECT_GT(o.crossings, 10000);
  EXPECT_LE(o.f_p50, q.f_p50);
  EXPECT_LE(o.f_p95, q.f_p95);
  // Crossings away from the data (spurious sheets): the away cells' quadrics held to 27
  // auxiliary points leave 166 of the 538 the 9 corner-and-centre points left, for both
  // kinds of fit (164 for the quadric's); the plates' two-sheet leaves, 156 (154); the 9
  // kept where the quadric held to them keeps their sign on the 27, 158 (156).
  EXPECT_LE(o.sheets, q.sheets + q.sheets / 10);
  EXPECT_LE(o.sheets, 200);
}

}  // namespace
}  // namespace mpumesh
