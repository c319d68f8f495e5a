// The single-precision MPU evaluation (common/eval_precision.h, core/mpu/mpu_eval_simd.h):
// the same bytes at every vector level this CPU runs (generic, AVX2, AVX-512), with each
// of the four evaluation orders; and its distance from the double-precision reference on
// fitted phantoms, at points within 3 mm of the surface: the worst difference in f and in
// the normal's direction, and within 0.5 mm (where the mesh's vertices lie) in the
// Gaussian curvature K of the blended Hessian; printed and bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "common/eval_precision.h"
#include "common/simd_level.h"
#include "mpu/mpu_eval_ref.h"
#include "mpu/mpu_fit.h"
#include "sample_bits.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// Restores the precision and the vector level when a test ends.
struct Restore {
  EvalPrecision precision = eval_precision();
  SimdLevel level = simd_level();
  ~Restore() {
    set_eval_precision(precision);
    set_simd_level(level);
  }
};

using test::same_bits;
using test::same_sample;

struct Phantom {
  const char* name;
  PointCloud cloud;
  mpu::MpuSurface surface;
};

// A sphere, a slice-stacked ellipsoid, a torus and a thin shell (two-sheet leaves), each
// fitted with the default options and indexed for both precisions.
std::vector<Phantom> phantoms() {
  test::AnalyticShape sphere, ellipsoid, torus;
  ellipsoid.kind = test::AnalyticShape::kEllipsoid;
  ellipsoid.a = 30, ellipsoid.b = 20, ellipsoid.c = 10;
  torus.kind = test::AnalyticShape::kTorus;
  torus.a = 25, torus.b = 8;
  std::vector<Phantom> out;
  out.push_back({"sphere, dense 1 mm", test::sample_shape(sphere, 1.0, 1.0, true), {}});
  out.push_back({"ellipsoid, slices 0.5 / 2 mm", test::sample_shape(ellipsoid, 0.5, 2.0, false), {}});
  out.push_back({"torus, dense 1 mm", test::sample_shape(torus, 1.0, 1.0, true), {}});
  out.push_back({"shell 20 / 18 mm", test::spherical_shell(20, 18), {}});
  for (Phantom& p : out) {
    p.surface = mpu::fit_mpu(p.cloud, {});
    set_eval_precision(EvalPrecision::kFloat);
    mpu::index_spheres(p.surface);
  }
  return out;
}

// Points on the cloud pushed along the normal by up to ±3 mm; with `far`, a third more
// up to ±30 mm off and some outside the bounding cube.
std::vector<Eigen::Vector3d> query_points(const Phantom& p, uint32_t seed, bool far) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> near(-3, 3), off(-30, 30), any(-0.2, 1.2);
  std::vector<Eigen::Vector3d> q;
  const PointCloud& c = p.cloud;
  for (int i = 0; i < 2000; ++i) {
    const size_t k = rng() % c.size();
    q.push_back(c.positions[k] + near(rng) * c.normals[k]);
  }
  for (int i = 0; far && i < 1003; ++i) {
    const size_t k = rng() % c.size();
    q.push_back(i % 3 ? c.positions[k] + off(rng) * c.normals[k]
                      : Eigen::Vector3d(p.surface.box_min +
                                        p.surface.box_size * test::random_vector(any, rng)));
  }
  return q;
}

TEST(MpuEvalFloat, EveryLevelGivesTheSameBytes) {
  Restore restore;
  const std::vector<Phantom> ps = phantoms();
  set_eval_precision(EvalPrecision::kFloat);
  uint32_t seed = 11;
  for (const Phantom& p : ps) {
    const std::vector<Eigen::Vector3d> q = query_points(p, seed++, true);
    for (SimdLevel level : {SimdLevel::kAvx2, SimdLevel::kAvx512}) {
      if (!simd_level_supported(level)) {
        std::printf("%s is not supported on this CPU: not compared\n", simd_level_name(level));
        continue;
      }
      int64_t bad = 0;
      for (const auto& x : q) {
        set_simd_level(SimdLevel::kGeneric);
        const mpu::Sample r3 = mpu::evaluate_hessian(p.surface, x), r2 = mpu::evaluate(p.surface, x),
                          r1 = mpu::evaluate_fg(p.surface, x);
        const double r0 = mpu::evaluate_f(p.surface, x);
        set_simd_level(level);
        const mpu::Sample v3 = mpu::evaluate_hessian(p.surface, x), v2 = mpu::evaluate(p.surface, x),
                          v1 = mpu::evaluate_fg(p.surface, x);
        const double v0 = mpu::evaluate_f(p.surface, x);
        bad += !same_sample(r3, v3) || !same_sample(r2, v2) || !same_sample(r1, v1) || !same_bits(r0, v0);
      }
      std::printf("float32 %s against generic, %s: %zu queries, %lld differ\n", simd_level_name(level), p.name,
                  q.size(), (long long)bad);
      EXPECT_EQ(bad, 0) << p.name << ", " << simd_level_name(level);
    }
  }
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
}

// The worst differences of the float path from the double reference: |Δf| in mm, the
// normal's angle in degrees, |ΔK| relative to the largest |K| within 0.5 mm.
TEST(MpuEvalFloat, StaysNearTheDoubleReference) {
  Restore restore;
  const std::vector<Phantom> ps = phantoms();
  constexpr double kF = 2e-5, kNormalDeg = 0.01, kCurvature = 1e-4;  // mm, degrees, of max |K|
  uint32_t seed = 5;
  for (const Phantom& p : ps) {
    const std::vector<Eigen::Vector3d> q = query_points(p, seed++, false);
    double df = 0, dn = 0, dK = 0, maxK = 0;
    for (const auto& x : q) {
      set_eval_precision(EvalPrecision::kDouble);
      const mpu::Sample d = mpu::evaluate(p.surface, x);
      set_eval_precision(EvalPrecision::kFloat);
      const mpu::Sample s = mpu::evaluate(p.surface, x);
      ASSERT_EQ(d.leaves, s.leaves);
      if (d.leaves == 0) continue;
      df = std::max(df, std::abs(d.f - s.f));
      dn = std::max(dn, angle_deg(d.g, s.g));
      if (std::abs(d.f) > 0.5) continue;
      const double Kd = mpu::curvature(d).gauss, Ks = mpu::curvature(s).gauss;
      maxK = std::max(maxK, std::abs(Kd));
      dK = std::max(dK, std::abs(Kd - Ks));
    }
    std::printf("float32 against float64, %s: %zu points within 3 mm; worst |df| %.2e mm, normal %.2e deg, "
                "within 0.5 mm |dK| %.2e /mm2 (%.2e of max |K| %.2e)\n",
                p.name, q.size(), df, dn, dK, dK / maxK, maxK);
    EXPECT_LT(df, kF) << p.name;
    EXPECT_LT(dn, kNormalDeg) << p.name;
    EXPECT_LT(dK, kCurvature * maxK) << p.name;
  }
}

}  // namespace
}  // namespace mpumesh
