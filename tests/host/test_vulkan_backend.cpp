// The Vulkan backend where core's stages use it beyond one kernel: the mesh optimisation
// (core/mesh/mesh_optimize.h) with its projections on the shader (particle_step_project.comp,
// float32) against the CPU reference's: the same jittered-sphere mesh optimised on both
// ends with the same flips and vertices within a micrometre of each other, and so the same
// shape figures; and one body on both backends against the truth. Validation on.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cpu/cpu_backend.h"
#include "mesh/mesh_optimize.h"
#include "mesh/restricted_delaunay.h"
#include "mpu/mpu_fit.h"
#include "particles/particle_step_ref.h"
#include "backends.h"
#include "error_stats.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// A sphere of radius 15 mm fitted, and the restricted Delaunay mesh of 1,203 points (not a
// multiple of a workgroup) jittered about a Fibonacci spiral and put back on its surface.
struct Jittered {
  test::AnalyticShape sphere{test::AnalyticShape::kSphere, 15, 15, 15};
  mpu::MpuSurface s;
  TriangleMesh start;
};

Jittered jittered_sphere() {
  Jittered j;
  j.s = mpu::fit_mpu(test::sample_shape(j.sphere, 0.5, 0.5, true), {});
  std::mt19937 rng(9);
  std::normal_distribution<double> jitter(0, 0.03);
  std::vector<Eigen::Vector3d> points;
  const int n = 1203;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d d = test::fibonacci_direction(k, n);
    const double jy = jitter(rng), jx = jitter(rng);  // y, then x
    Eigen::Vector3d p = 15 * Eigen::Vector3d(d.x() + jx, d.y() + jy, d.z());
    particles::newton_project(j.s, p, 8, 5.0);
    points.push_back(p);
  }
  j.start = restricted_delaunay(j.s, points);
  return j;
}

TEST(MeshOptimizeVk, MatchesTheCpuPath) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Jittered j = jittered_sphere();
  const mpu::MpuSurface& s = j.s;
  const TriangleMesh& start = j.start;
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

// One body on both backends against the truth: the optimisation raises the jittered
// sphere's mean radius ratio and smallest angle, and its vertices stay on the sphere.
class OptimizeBackends : public test::BackendTest {};

TEST_P(OptimizeBackends, ShapesTheJitteredSphereOnItsSurface) {
  MPUMESH_BACKEND_OR_SKIP(backend);
  const Jittered j = jittered_sphere();
  TriangleMesh m = j.start;
  const OptimizeStats st = optimize_mesh(m, j.s, backend, std::vector<double>(m.vertices.size(), 1.3));
  test::ErrorStats off;
  for (const auto& v : m.vertices) off.add_error(j.sphere.distance(v));
  std::printf("[ %s ] radius ratio %.4f -> %.4f, smallest angle %.2f -> %.2f deg; %s mm\n", GetParam().c_str(),
              st.before.radius_ratio, st.after.radius_ratio, st.before.min_angle_deg, st.after.min_angle_deg,
              off.line("off the sphere").c_str());
  EXPECT_GT(st.after.radius_ratio, st.before.radius_ratio);
  EXPECT_GE(st.after.min_angle_deg, st.before.min_angle_deg);
  EXPECT_LT(off.max_abs, 0.01);
}
MPUMESH_INSTANTIATE_BACKENDS(OptimizeBackends);

}  // namespace
}  // namespace mpumesh
