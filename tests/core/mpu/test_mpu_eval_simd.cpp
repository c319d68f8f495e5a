// The MPU evaluation's vector paths (core/mpu/mpu_eval_simd.h, one per SimdLevel of
// common/simd_level.h) against the generic
// reference (core/mpu/mpu_eval_ref.cpp): the same bytes for f, ∇f, the blended Hessian,
// the Hessian and the leaf count, on fitted phantoms (a sphere, a slice-stacked ellipsoid,
// a torus, a thin spherical shell whose leaves hold two sheets), at random points on, near, far from and outside the surface, with each of the
// four evaluation orders; and the fall-back to the reference where a lookup cell holds more
// candidates than the kernels buffer. Paths this CPU lacks are skipped, and say so.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "common/simd_level.h"
#include "mpu/mpu_eval_ref.h"
#include "mpu/mpu_eval_simd.h"
#include "mpu/mpu_fit.h"
#include "sample_bits.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// Restores the vector level when a test ends.
struct LevelGuard {
  SimdLevel saved = simd_level();
  ~LevelGuard() { set_simd_level(saved); }
};

using test::same_bits;
using test::same_sample;

// Points on the fitted cloud, pushed along the normal by up to ±3 mm, a few far off
// (±30 mm) and a few outside the bounding cube; 2,000 + 1,003 of them (not a multiple of
// eight).
std::vector<Eigen::Vector3d> query_points(const PointCloud& c, const mpu::MpuSurface& s, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> near(-3, 3), far(-30, 30), any(-0.2, 1.2);
  std::vector<Eigen::Vector3d> q;
  for (int i = 0; i < 2000; ++i) {
    const size_t k = rng() % c.size();
    q.push_back(c.positions[k] + near(rng) * c.normals[k]);
  }
  for (int i = 0; i < 1003; ++i) {
    const size_t k = rng() % c.size();
    q.push_back(i % 3 ? c.positions[k] + far(rng) * c.normals[k]
                      : Eigen::Vector3d(s.box_min + s.box_size * test::random_vector(any, rng)));
  }
  return q;
}

// Evaluates every query with every order on `path` and on the reference; returns the
// count of differing results, and sets `leaves` to the mean leaves per inside query.
int64_t mismatches(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& q, SimdLevel path, double* leaves) {
  int64_t bad = 0, held = 0, sum = 0;
  for (const auto& x : q) {
    set_simd_level(SimdLevel::kGeneric);
    const mpu::Sample r3 = mpu::evaluate_hessian(s, x), r2 = mpu::evaluate(s, x), r1 = mpu::evaluate_fg(s, x);
    const double r0 = mpu::evaluate_f(s, x);
    set_simd_level(path);
    const mpu::Sample v3 = mpu::evaluate_hessian(s, x), v2 = mpu::evaluate(s, x), v1 = mpu::evaluate_fg(s, x);
    const double v0 = mpu::evaluate_f(s, x);
    bad += !same_sample(r3, v3) || !same_sample(r2, v2) || !same_sample(r1, v1) || !same_bits(r0, v0);
    if (r2.leaves > 0) {
      ++held;
      sum += r2.leaves;
    }
  }
  *leaves = held ? double(sum) / double(held) : 0;
  return bad;
}

class MpuEvalSimd : public ::testing::TestWithParam<SimdLevel> {};

TEST_P(MpuEvalSimd, GivesTheReferenceBytesOnPhantoms) {
  const SimdLevel path = GetParam();
  if (!simd_level_supported(path)) GTEST_SKIP() << simd_level_name(path) << " is not supported on this CPU";
  LevelGuard guard;
  struct Case {
    const char* name;
    test::AnalyticShape shape;
    double h_xy, h_z;
    bool dense;
  };
  test::AnalyticShape sphere, ellipsoid, torus;
  ellipsoid.kind = test::AnalyticShape::kEllipsoid;
  ellipsoid.a = 30, ellipsoid.b = 20, ellipsoid.c = 10;
  torus.kind = test::AnalyticShape::kTorus;
  torus.a = 25, torus.b = 8;
  const Case cases[] = {{"sphere, dense 1 mm", sphere, 1.0, 1.0, true},
                        {"ellipsoid, slices 0.5 / 2 mm", ellipsoid, 0.5, 2.0, false},
                        {"torus, dense 1 mm", torus, 1.0, 1.0, true}};
  uint32_t seed = 7;
  for (const Case& c : cases) {
    const PointCloud cloud = test::sample_shape(c.shape, c.h_xy, c.h_z, c.dense);
    const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
    const std::vector<Eigen::Vector3d> q = query_points(cloud, s, seed++);
    double leaves = 0;
    const int64_t bad = mismatches(s, q, path, &leaves);
    std::printf("%s, %s: %zu leaves, %zu queries (%.1f leaves each where held), %lld differ\n",
                simd_level_name(path), c.name, s.leaves.size(), q.size(), leaves, (long long)bad);
    EXPECT_EQ(bad, 0) << c.name;
  }
  // Every term of the basis: the shell's two-sheet leaves (local_fit.h) use 0-21.
  const PointCloud shell = test::spherical_shell(20, 18);
  mpu::FitStats st;
  const mpu::MpuSurface s = mpu::fit_mpu(shell, {}, &st);
  ASSERT_GT(st.two_sheets, 0);
  double leaves = 0;
  const int64_t bad = mismatches(s, query_points(shell, s, seed), path, &leaves);
  std::printf("%s, shell 20/18 mm: %zu leaves (%lld two sheets), %lld differ\n", simd_level_name(path), s.leaves.size(),
              (long long)st.two_sheets, (long long)bad);
  EXPECT_EQ(bad, 0);
}

TEST_P(MpuEvalSimd, FallsBackToTheReferenceOnCrowdedCells) {
  const SimdLevel path = GetParam();
  if (!simd_level_supported(path)) GTEST_SKIP() << simd_level_name(path) << " is not supported on this CPU";
  LevelGuard guard;
  // A lookup grid of 2 x 2 x 2 cells over an ellipsoid fitted to 1 µm (down to small
  // leaves): each cell lists more leaves than the kernels buffer, so they decline and the
  // reference answers.
  const PointCloud cloud = test::sample_shape({test::AnalyticShape::kEllipsoid, 30, 20, 10}, 0.5, 0.5, true);
  mpu::FitOptions o;
  o.grid_cells = 2;
  o.eps = 0.001;
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, o);
  uint32_t most = 0;
  for (size_t c = 0; c + 1 < s.grid.offsets.size(); ++c) most = std::max(most, s.grid.offsets[c + 1] - s.grid.offsets[c]);
  ASSERT_GT(most, mpu::simd::kMaxCandidates);
  double leaves = 0;
  EXPECT_EQ(mismatches(s, query_points(cloud, s, 3), path, &leaves), 0);
}

INSTANTIATE_TEST_SUITE_P(Levels, MpuEvalSimd, ::testing::Values(SimdLevel::kAvx2, SimdLevel::kAvx512),
                         [](const auto& info) { return std::string(simd_level_name(info.param)); });

TEST(SimdLevel, TheWidestSupportedIsTaken) {
  // Unless MPUMESH_SIMD names another, the default is the widest this CPU runs.
  if (std::getenv("MPUMESH_SIMD")) GTEST_SKIP() << "MPUMESH_SIMD is set";
  const SimdLevel expect = simd_level_supported(SimdLevel::kAvx512) ? SimdLevel::kAvx512
                          : simd_level_supported(SimdLevel::kAvx2) ? SimdLevel::kAvx2
                                                                       : SimdLevel::kGeneric;
  EXPECT_EQ(simd_level(), expect) << simd_level_name(simd_level());
}

}  // namespace
}  // namespace mpumesh
