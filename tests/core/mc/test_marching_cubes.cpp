// Marching cubes against an analytic sphere at anisotropic spacing, the threshold field,
// and the errors for thresholds that select nothing or everything.
#include <gtest/gtest.h>

#include <numbers>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "mc/marching_cubes.h"
#include "mesh/quality.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(McField, PadsAndSignsTheThresholdRange) {
  Volume v;
  v.dims = {2, 1, 1};
  v.voxels = {100, 300};
  const mc::McField f = mc::make_threshold_field(v, {50, 200});
  ASSERT_EQ(f.dims, (std::array<int64_t, 3>{4, 3, 3}));
  EXPECT_FLOAT_EQ(f.values[size_t(1 + 4 * (1 + 3 * 1))], 50.0f);    // min(100-50, 200-100)
  EXPECT_FLOAT_EQ(f.values[size_t(2 + 4 * (1 + 3 * 1))], -100.0f);  // above HI
  EXPECT_LT(f.values[0], 0.0f);                                     // padding is outside
}

TEST(McField, ParsesThresholds) {
  EXPECT_DOUBLE_EQ(mc::parse_threshold("226").lo, 226);
  EXPECT_TRUE(std::isinf(mc::parse_threshold("226").hi));
  EXPECT_DOUBLE_EQ(mc::parse_threshold("-100:300").hi, 300);
  EXPECT_THROW(mc::parse_threshold("abc"), InputError);
  EXPECT_THROW(mc::parse_threshold("300:100"), InputError);
  EXPECT_THROW(mc::parse_threshold("1:"), InputError);
}

TEST(MarchingCubes, SphereAtAnisotropicSpacing) {
  const double r = 10.0;
  const Eigen::Vector3d spacing(0.5, 0.5, 2.0), centre(16, 16, 24);
  const Volume v = test::sphere_volume({64, 64, 24}, spacing, centre, r);
  CpuBackend cpu;
  const TriangleMesh m = marching_cubes(v, {0.0}, cpu);
  const Quality q = measure_quality(m);
  EXPECT_TRUE(q.topo.closed && q.topo.manifold && q.topo.oriented);
  EXPECT_EQ(q.topo.components, 1);
  EXPECT_EQ(q.topo.genus, 0);
  EXPECT_EQ(q.self_intersections, 0);
  EXPECT_NEAR(q.volume_mm3, 4.0 / 3.0 * std::numbers::pi * r * r * r, 0.02 * 4.19e3);
  EXPECT_NEAR(q.area_mm2, 4.0 * std::numbers::pi * r * r, 0.03 * 1257.0);
  double worst = 0;
  for (const auto& p : m.vertices) worst = std::max(worst, std::abs((p - centre).norm() - r));
  // Linear interpolation across a 2 mm slice: within a quarter of the slice spacing.
  EXPECT_LT(worst, 0.5);
}

TEST(MarchingCubes, MirroredDirectionKeepsNormalsOutward) {
  Volume v = test::sphere_volume({20, 20, 20}, {1, 1, 1}, {10, 10, 10}, 6);
  v.direction = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  CpuBackend cpu;
  const Quality q = measure_quality(marching_cubes(v, {0.0}, cpu), {.self_intersections = false});
  EXPECT_GT(q.volume_mm3, 0);
}

TEST(MarchingCubes, StructureTouchingTheBorderCloses) {
  Volume v;
  v.dims = {4, 4, 4};
  v.voxels.assign(64, 500.0f);  // all inside but one voxel
  v.voxels[0] = -500.0f;
  CpuBackend cpu;
  const Topology t = analyze_topology(marching_cubes(v, {0.0}, cpu));
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
}

TEST(MarchingCubes, NoSurfaceIsAnError) {
  Volume v;
  v.dims = {3, 3, 3};
  v.voxels.assign(27, 10.0f);
  v.source = "flat.nii";
  CpuBackend cpu;
  try {
    marching_cubes(v, {100.0}, cpu);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("flat.nii"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("selects no voxel"), std::string::npos);
  }
  EXPECT_THROW(marching_cubes(v, {0.0}, cpu), InputError);  // every voxel
}

}  // namespace
}  // namespace mpumesh
