// The mesh optimisation (core/mesh/mesh_optimize.h) with its projections on the shader
// (particle_step_project.comp, float32, through the Vulkan backend) against the CPU
// reference's: the same jittered-sphere mesh optimised on both ends with the same flips and
// vertices within a micrometre of each other, and so the same shape figures; validation on.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cpu/cpu_backend.h"
#include "mesh/mesh_optimize.h"
#include "mesh/restricted_delaunay.h"
#include "mpu/mpu_fit.h"
#include "particles/particle_step_ref.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(MeshOptimizeVk, MatchesTheCpuPath) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 15, 15, 15};
  const mpu::MpuSurface s = mpu::fit_mpu(test::sample_shape(sphere, 0.5, 0.5, true), {});
  std::mt19937 rng(9);
  std::normal_distribution<double> jitter(0, 0.03);
  std::vector<Eigen::Vector3d> points;
  const int n = 1203;  // not a multiple of a workgroup
  for (int k = 0; k < n; ++k) {
    const double z = 1 - (2 * k + 1.0) / n, rho = std::sqrt(1 - z * z), phi = k * M_PI * (3 - std::sqrt(5.0));
    Eigen::Vector3d p = 15 * Eigen::Vector3d(rho * std::cos(phi) + jitter(rng), rho * std::sin(phi) + jitter(rng), z);
    particles::newton_project(s, p, 8, 5.0);
    points.push_back(p);
  }
  const TriangleMesh start = restricted_delaunay(s, points);
  const std::vector<double> spacing(start.vertices.size(), 1.3);
  TriangleMesh a = start, b = start;
  CpuBackend cpu;
  const OptimizeStats sa = optimize_mesh(a, s, cpu, spacing), sb = optimize_mesh(b, s, *gpu, spacing);
  EXPECT_EQ(sa.collapses, sb.collapses);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  double worst = 0;
  for (size_t v = 0; v < a.vertices.size(); ++v) worst = std::max(worst, (a.vertices[v] - b.vertices[v]).norm());
  std::printf("CPU: %lld flips, %lld collapses, radius ratio %.5f, smallest %.3f deg; GPU: %lld flips, %lld "
              "collapses, %.5f, %.3f deg; vertices within %.2e mm\n",
              (long long)sa.flips, (long long)sa.collapses, sa.after.radius_ratio, sa.after.min_angle_deg,
              (long long)sb.flips, (long long)sb.collapses, sb.after.radius_ratio, sb.after.min_angle_deg, worst);
  EXPECT_GT(sa.after.radius_ratio, sa.before.radius_ratio);
  EXPECT_EQ(sa.flips, sb.flips);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_LT(worst, 1e-3);
  EXPECT_NEAR(sa.after.radius_ratio, sb.after.radius_ratio, 1e-4);
  EXPECT_NEAR(sa.after.min_angle_deg, sb.after.min_angle_deg, 0.01);
  test::expect_no_validation_messages(*gpu);
}

}  // namespace
}  // namespace mpumesh
