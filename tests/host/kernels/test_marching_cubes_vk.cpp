// Marching cubes: one test body on both backends against the analytic sphere, and the
// shader against the CPU reference: identical connectivity and vertex order, positions
// within float precision, on random fields whose sizes are not workgroup multiples and on
// the real sample CT.
#include <gtest/gtest.h>

#include "cpu/cpu_backend.h"
#include "mc/marching_cubes.h"
#include "mesh/topology.h"
#include "io/volume_io.h"
#include "backends.h"
#include "error_stats.h"
#include "test_support.h"
#include "mc/marching_cubes_ref.h"

namespace mpumesh {
namespace {

// Float vertex positions in grid units: the GPU computes t in float32.
constexpr double kGridTolerance = 2e-5;

// The shader's vertex coordinates (grid units) against the reference's; the connectivity
// must be the same.
test::ErrorStats compare(const mc::McMesh& cpu, const mc::McMesh& gpu) {
  EXPECT_EQ(cpu.triangles.size(), gpu.triangles.size());
  EXPECT_EQ(cpu.grid_vertices.size(), gpu.grid_vertices.size());
  EXPECT_TRUE(cpu.triangles == gpu.triangles) << "connectivity differs";
  test::ErrorStats d;
  const size_t n = std::min(cpu.grid_vertices.size(), gpu.grid_vertices.size());
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) d.add(gpu.grid_vertices[i][size_t(a)], cpu.grid_vertices[i][size_t(a)]);
  return d;
}

class McBackends : public test::BackendTest {};

TEST_P(McBackends, SphereIsClosedAndOnTheSurface) {
  MPUMESH_BACKEND_OR_SKIP(backend);
  const Eigen::Vector3d centre(12, 11, 14);
  const Volume v = test::sphere_volume({47, 45, 15}, {0.5, 0.5, 2.0}, centre, 8.0);
  const TriangleMesh m = marching_cubes(v, {0.0}, backend);
  const Topology t = analyze_topology(m);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_EQ(t.genus, 0);
  for (const auto& p : m.vertices) ASSERT_NEAR((p - centre).norm(), 8.0, 0.5);
}
MPUMESH_INSTANTIATE_BACKENDS(McBackends);

TEST(McVk, RandomFieldsMatchTheReference) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    const std::array<int64_t, 3> dims{13 + seed, 7 + 2 * seed, 5 + seed};
    const Volume v = test::random_volume(dims, 0.3 + 0.07 * seed, seed);
    const mc::McField field = mc::make_threshold_field(v, {0.0});
    const test::ErrorStats d = compare(mc::marching_cubes_ref(field), gpu->marching_cubes(field));
    EXPECT_LT(d.max_abs, kGridTolerance) << "seed " << seed;
    std::printf("seed %u: %lld points, %s (grid units)\n", seed, (long long)field.point_count(),
                d.line("x").c_str());
  }
  test::expect_no_validation_messages(*gpu);
}

TEST(McVk, SampleCtMatchesTheReference) {
  MPUMESH_SAMPLE_CT_OR_SKIP(ct);
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Volume v = read_volume(ct);
  const mc::McField field = mc::make_threshold_field(v, {226.0});
  const mc::McMesh cpu = mc::marching_cubes_ref(field);
  const mc::McMesh gm = gpu->marching_cubes(field);
  const test::ErrorStats d = compare(cpu, gm);
  EXPECT_LT(d.max_abs, kGridTolerance);
  std::printf("sample CT: %zu vertices, %zu triangles, %s (grid units)\n", cpu.grid_vertices.size(),
              cpu.triangles.size(), d.line("x").c_str());
  const Topology t = analyze_topology(grid_mesh_to_physical(gm, v));
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_EQ(t.components, 187);
  test::expect_no_validation_messages(*gpu);
}

}  // namespace
}  // namespace mpumesh
