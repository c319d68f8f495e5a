// MPU evaluation: the shader (mpu_eval.comp, float32) against the double-precision CPU
// reference (core/mpu/mpu_eval_ref.cpp) on 10^5 random points near fitted surfaces, with
// validation on: |Δf| <= 1e-4 mm, gradient angle <= 0.01°, curvature within 1e-3
// relative where |K| is not tiny.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cpu/cpu_backend.h"
#include "mpu/mpu_fit.h"
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

struct Diff {
  double f = 0, angle_deg = 0, gauss_rel = 0, kappa_rel = 0;
  size_t curved = 0;  // points where |K| was not tiny
};

Diff compare(const std::vector<mpu::EvalRow>& c, const std::vector<mpu::EvalRow>& g, double K_floor) {
  Diff d;
  for (size_t i = 0; i < c.size(); ++i) {
    d.f = std::max(d.f, std::abs(c[i].f - g[i].f));
    const Eigen::Vector3d a(c[i].g[0], c[i].g[1], c[i].g[2]), b(g[i].g[0], g[i].g[1], g[i].g[2]);
    if (a.norm() > 0) d.angle_deg = std::max(d.angle_deg, std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI);
    if (std::abs(c[i].gauss) < K_floor) continue;
    ++d.curved;
    d.gauss_rel = std::max(d.gauss_rel, std::abs(c[i].gauss - g[i].gauss) / std::abs(c[i].gauss));
    const double kmax = std::max(std::abs(c[i].k1), std::abs(c[i].k2));
    d.kappa_rel = std::max({d.kappa_rel, std::abs(c[i].k1 - g[i].k1) / kmax, std::abs(c[i].k2 - g[i].k2) / kmax});
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
  std::printf("[ %s ] %zu leaves, %zu points (%zu curved): max |df| %.2e mm, angle %.2e deg, K rel %.2e, "
              "kappa rel %.2e; CPU %.0f ms, GPU %.0f ms\n",
              c.name, s.leaves.size(), points.size(), d.curved, d.f, d.angle_deg, d.gauss_rel, d.kappa_rel,
              cpu.kernel_ms().at("mpu_eval"), gpu->kernel_ms().at("mpu_eval"));
  EXPECT_GT(d.curved, points.size() / 2);
  EXPECT_LE(d.f, 1e-4);
  EXPECT_LE(d.angle_deg, 0.01);
  EXPECT_LE(d.gauss_rel, 1e-3);
  EXPECT_LE(d.kappa_rel, 1e-3);
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
  std::printf("[ shell 20/18 ] %zu leaves (%lld two sheets), %zu points (%zu curved): max |df| %.2e mm, angle %.2e "
              "deg, K rel %.2e, kappa rel %.2e\n",
              s.leaves.size(), (long long)st.two_sheets, points.size(), d.curved, d.f, d.angle_deg, d.gauss_rel,
              d.kappa_rel);
  EXPECT_GT(d.curved, points.size() / 2);
  EXPECT_LE(d.f, 1e-4);
  EXPECT_LE(d.angle_deg, 0.01);
  EXPECT_LE(d.gauss_rel, 1e-3);
  EXPECT_LE(d.kappa_rel, 1e-3);
  test::expect_no_validation_messages(*gpu);
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, MpuEvalVk,
    ::testing::Values(Case{"ellipsoid_dense", {test::AnalyticShape::kEllipsoid, 30, 20, 10}, true, 1.0 / (20.0 * 20.0)},
                      Case{"torus_slices", {test::AnalyticShape::kTorus, 25, 8, 8}, false, 1.0 / (8.0 * 33.0)}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace mpumesh
