// MPU evaluation: the shader (mpu_eval.comp, float32) against the double-precision CPU
// reference (core/mpu/mpu_eval_ref.cpp) on 10^5 random points near fitted surfaces, with
// validation on: |Δf| <= 1e-4 mm, gradient angle <= 0.01°, curvature within 1e-3
// relative where |K| is not tiny.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cpu/cpu_backend.h"
#include "mpu/mpu_fit.h"
#include "backends.h"
#include "error_stats.h"
#include "test_support.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh {
namespace {

// n points within ±band mm of the true surface, along its normal.
std::vector<Eigen::Vector3d> near_surface(const test::AnalyticShape& shape, size_t n, double band, uint32_t seed) {
  const PointCloud truth = test::sample_shape(shape, 0.37, 0.37, true);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, truth.size() - 1);
  std::uniform_real_distribution<double> off(-band, band);
  std::vector<Eigen::Vector3d> out(n);
  for (auto& p : out) {
    const size_t i = pick(rng);
    p = truth.positions[i] + off(rng) * truth.normals[i];
  }
  return out;
}

// The shader's rows against the reference's: f (mm), the gradient's direction (degrees),
// K and the larger |κ| relative where |K| is not tiny.
struct Diff {
  test::ErrorStats f, angle_deg, gauss, kappa;
};

Diff compare(const std::vector<mpu::EvalRow>& c, const std::vector<mpu::EvalRow>& g, double K_floor) {
  Diff d;
  for (size_t i = 0; i < c.size(); ++i) {
    d.f.add(g[i].f, c[i].f);
    const Eigen::Vector3d a(c[i].g[0], c[i].g[1], c[i].g[2]), b(g[i].g[0], g[i].g[1], g[i].g[2]);
    if (a.norm() > 0) d.angle_deg.add_error(std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI);
    if (std::abs(c[i].gauss) < K_floor) continue;
    d.gauss.add(g[i].gauss, c[i].gauss, K_floor);
    const double kmax = std::max(std::abs(c[i].k1), std::abs(c[i].k2));
    d.kappa.add_error(std::max(std::abs(c[i].k1 - g[i].k1), std::abs(c[i].k2 - g[i].k2)) / kmax);
  }
  return d;
}

struct Case {
  const char* name;
  test::AnalyticShape shape;
  bool dense;
  double K_scale;  // 1/mm², the shape's typical |K|
};

class MpuEvalVk : public ::testing::TestWithParam<Case> {};

TEST_P(MpuEvalVk, MatchesTheReferenceOnPointsNearTheSurface) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Case& c = GetParam();
  const mpu::MpuSurface s = mpu::fit_mpu(test::sample_shape(c.shape, 0.5, c.dense ? 0.5 : 2.0, c.dense), {});
  const auto points = near_surface(c.shape, 100000, 2.0, 7);
  CpuBackend cpu;
  const auto rc = cpu.mpu_eval(s, points);
  const auto rg = gpu->mpu_eval(s, points);
  ASSERT_EQ(rc.size(), rg.size());
  // "Not tiny": |K| at least 10% of the shape's scale. Below it, K = κ1 κ2 with a small κ2
  // magnifies κ2's float error, which the κ check bounds against the larger |κ| anyway.
  const Diff d = compare(rc, rg, 0.1 * c.K_scale);
  std::printf("[ %s ] %zu leaves, %zu points; %s mm; %s deg; %s; %s; CPU %.0f ms, GPU %.0f ms\n", c.name,
              s.leaves.size(), points.size(), d.f.line("f").c_str(), d.angle_deg.line("normal").c_str(),
              d.gauss.line("K").c_str(), d.kappa.line("kappa (of the larger)").c_str(), cpu.kernel_ms().at("mpu_eval"),
              gpu->kernel_ms().at("mpu_eval"));
  EXPECT_GT(d.gauss.n, points.size() / 2);
  EXPECT_LE(d.f.max_abs, 1e-4);
  EXPECT_LE(d.angle_deg.max_abs, 0.01);
  EXPECT_LE(d.gauss.max_rel, 1e-3);
  EXPECT_LE(d.kappa.max_abs, 1e-3);
  // f alone (the shader's value_only mode; the triangulation's Voronoi vertices).
  const std::vector<double> fc = cpu.mpu_f(s, points), fg = gpu->mpu_f(s, points);
  ASSERT_EQ(fc.size(), points.size());
  ASSERT_EQ(fg.size(), points.size());
  double df = 0, dself = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    df = std::max(df, std::abs(fc[i] - fg[i]));
    dself = std::max(dself, std::abs(fc[i] - rc[i].f));
  }
  std::printf("[ %s ] f alone: max |df| %.2e mm (CPU f alone vs with the rest: %.2e)\n", c.name, df, dself);
  EXPECT_LE(df, 1e-4);
  EXPECT_LE(dself, 1e-12);
  test::expect_no_validation_messages(*gpu);
}

// The thin spherical shell's leaves hold two sheets (every term of local_poly.h's basis,
// three of them in the leaf's spare components: shaders/shared/mpu_abi.h).
TEST(MpuEvalVk, MatchesTheReferenceOnTwoSheetLeaves) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const PointCloud shell = test::spherical_shell(20, 18);
  mpu::FitStats st;
  const mpu::MpuSurface s = mpu::fit_mpu(shell, {}, &st);
  ASSERT_GT(st.two_sheets, 0);
  std::vector<Eigen::Vector3d> points;
  std::mt19937 rng(11);
  std::uniform_int_distribution<size_t> pick(0, shell.size() - 1);
  std::uniform_real_distribution<double> off(-0.8, 0.8);
  for (int i = 0; i < 50000; ++i) {
    const size_t k = pick(rng);
    points.push_back(shell.positions[k] + off(rng) * shell.normals[k]);
  }
  CpuBackend cpu;
  const auto rc = cpu.mpu_eval(s, points);
  const auto rg = gpu->mpu_eval(s, points);
  ASSERT_EQ(rc.size(), rg.size());
  const Diff d = compare(rc, rg, 0.1 / (20.0 * 20.0));
  std::printf("[ shell 20/18 ] %zu leaves (%lld two sheets), %zu points; %s mm; %s deg; %s; %s\n", s.leaves.size(),
              (long long)st.two_sheets, points.size(), d.f.line("f").c_str(), d.angle_deg.line("normal").c_str(),
              d.gauss.line("K").c_str(), d.kappa.line("kappa (of the larger)").c_str());
  EXPECT_GT(d.gauss.n, points.size() / 2);
  EXPECT_LE(d.f.max_abs, 1e-4);
  EXPECT_LE(d.angle_deg.max_abs, 0.01);
  EXPECT_LE(d.gauss.max_rel, 1e-3);
  EXPECT_LE(d.kappa.max_abs, 1e-3);
  test::expect_no_validation_messages(*gpu);
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, MpuEvalVk,
    ::testing::Values(Case{"ellipsoid_dense", {test::AnalyticShape::kEllipsoid, 30, 20, 10}, true, 1.0 / (20.0 * 20.0)},
                      Case{"torus_slices", {test::AnalyticShape::kTorus, 25, 8, 8}, false, 1.0 / (8.0 * 33.0)}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

// One body on both backends against the truth: at points on a fitted ellipsoid's true
// surface, f within 1% of the sampling spacing, the normal within 2° and K within 5% (rms)
// of the analytic ones.
class MpuEvalBackends : public test::BackendTest {};

TEST_P(MpuEvalBackends, TheFittedEllipsoidAtItsTrueSurface) {
  MPUMESH_BACKEND_OR_SKIP(backend);
  const test::AnalyticShape shape{test::AnalyticShape::kEllipsoid, 30, 20, 10};
  const mpu::MpuSurface s = mpu::fit_mpu(test::sample_shape(shape, 0.5, 0.5, true), {});
  const PointCloud truth = test::sample_shape(shape, 0.37, 0.37, true);
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < truth.size(); i += 7) points.push_back(truth.positions[i]);
  const std::vector<mpu::EvalRow> rows = backend.mpu_eval(s, points);
  ASSERT_EQ(rows.size(), points.size());
  test::ErrorStats f, normal_deg, gauss_rel;
  for (size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector3d n;
    double K;
    shape.distance(points[i], &n, &K);
    f.add_error(std::abs(rows[i].f));
    const Eigen::Vector3d g(rows[i].g[0], rows[i].g[1], rows[i].g[2]);
    normal_deg.add_error(std::atan2(g.cross(n).norm(), g.dot(n)) * 180 / M_PI);
    gauss_rel.add_error(std::abs(rows[i].gauss - K) / std::abs(K));
  }
  std::printf("[ %s ] %zu points: %s mm; %s deg; %s\n", GetParam().c_str(), points.size(), f.line("|f|").c_str(),
              normal_deg.line("normal").c_str(), gauss_rel.line("K relative").c_str());
  EXPECT_LE(f.max_abs, 0.005);
  EXPECT_LE(normal_deg.max_abs, 2.0);
  EXPECT_LE(gauss_rel.rms(), 0.05);
}
MPUMESH_INSTANTIATE_BACKENDS(MpuEvalBackends);

}  // namespace
}  // namespace mpumesh
