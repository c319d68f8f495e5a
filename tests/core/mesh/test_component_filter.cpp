// core/mesh/component_filter: keeping the largest structures of a closed mesh, with their
// cavities, and dropping small ones.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/component_filter.h"
#include "mesh/topology.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// Appends `part` moved by `at`, reversed (facing inward: a cavity's wall) when `inward`.
void add(TriangleMesh& m, TriangleMesh part, const Eigen::Vector3d& at, bool inward = false) {
  const uint32_t base = uint32_t(m.vertices.size());
  for (auto& v : part.vertices) m.vertices.push_back(v + at);
  for (auto t : part.triangles) {
    if (inward) std::swap(t[1], t[2]);
    m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
}

// A 10 mm ball, a hollow ball (8 mm with a 6 mm cavity) and a 5 mm ball, apart.
TriangleMesh three_structures() {
  TriangleMesh m;
  add(m, test::icosphere(10, 3), {0, 0, 0});
  add(m, test::icosphere(8, 3), {40, 0, 0});
  add(m, test::icosphere(6, 3), {40, 0, 0}, true);
  add(m, test::icosphere(5, 3), {0, 40, 0});
  m.normals.assign(m.vertices.size(), Eigen::Vector3f(0, 0, 1));
  return m;
}

TEST(ComponentOptions, KeepsTheLargestWithTheirCavities) {
  const TriangleMesh m = three_structures();
  const double hollow = 4.0 / 3 * M_PI * (512 - 216), small = 4.0 / 3 * M_PI * 125;
  ComponentOptions f;
  f.largest = 1;
  FilteredMesh one = filter_components(m, f);
  EXPECT_EQ(one.kept, 1);
  EXPECT_EQ(analyze_topology(one.mesh).components, 1);
  EXPECT_EQ(one.mesh.normals.size(), one.mesh.vertices.size()) << "the attributes follow the kept vertices";
  for (const auto& v : one.mesh.vertices) EXPECT_NEAR(v.norm(), 10, 0.01);
  ASSERT_EQ(one.dropped.size(), 2u);
  EXPECT_NEAR(one.dropped[0].volume_mm3, hollow, 0.03 * hollow) << "the hollow ball, its cavity subtracted";
  EXPECT_NEAR(one.dropped[1].volume_mm3, small, 0.03 * small);
  EXPECT_NEAR(one.dropped[0].centre.x(), 40, 0.5);

  f.largest = 2;
  FilteredMesh two = filter_components(m, f);
  EXPECT_EQ(two.kept, 2);
  EXPECT_EQ(analyze_topology(two.mesh).components, 3) << "the hollow ball keeps its cavity";
  EXPECT_EQ(two.dropped.size(), 1u);

  ComponentOptions by_volume;
  by_volume.min_volume_mm3 = 0.5 * (small + hollow);
  FilteredMesh v = filter_components(m, by_volume);
  EXPECT_EQ(v.kept, 2);
  ASSERT_EQ(v.dropped.size(), 1u);
  EXPECT_NEAR(v.dropped[0].centre.y(), 40, 0.5) << "the small ball is dropped";
}

TEST(ComponentOptions, SplitsAMeshIntoItsPartsLargestFirstEachWithItsCavities) {
  const TriangleMesh m = three_structures();
  const std::vector<MeshPart> parts = split_parts(m);
  ASSERT_EQ(parts.size(), 3u);
  const double big = 4.0 / 3 * M_PI * 1000, hollow = 4.0 / 3 * M_PI * (512 - 216), small = 4.0 / 3 * M_PI * 125;
  EXPECT_NEAR(parts[0].volume_mm3, big, 0.03 * big);
  EXPECT_NEAR(parts[1].volume_mm3, hollow, 0.03 * hollow);
  EXPECT_NEAR(parts[2].volume_mm3, small, 0.03 * small);
  const Topology hollow_topology = analyze_topology(parts[1].mesh);
  EXPECT_EQ(hollow_topology.components, 2) << "the hollow ball with its cavity";
  EXPECT_TRUE(hollow_topology.oriented);
  EXPECT_NEAR(parts[1].mesh.vertices[0].x(), 40, 8.01);
  size_t triangles = 0;
  for (const MeshPart& p : parts) triangles += p.mesh.triangles.size();
  EXPECT_EQ(triangles, m.triangles.size());
}

TEST(ComponentOptions, DropsEverythingBelowTheVolumeAsked) {
  ComponentOptions f;
  f.min_volume_mm3 = 1e6;
  const FilteredMesh r = filter_components(three_structures(), f);
  EXPECT_EQ(r.kept, 0);
  EXPECT_TRUE(r.mesh.triangles.empty());
  EXPECT_EQ(r.dropped.size(), 3u);
}

// A sheet folded onto itself: a flattened ball (every vertex squeezed to 0.02 mm in z), two
// sides 0.02 mm apart at most, enclosing next to nothing; and a thin plate (a 10 x 10 x 0.5
// mm box) beside the three structures.
TEST(ComponentOptions, DropsSheetsThatEncloseNothingAndKeepsThinPlates) {
  TriangleMesh m = three_structures();
  TriangleMesh sheet = test::icosphere(6, 3);
  for (auto& v : sheet.vertices) v.z() *= 0.02 / 6;
  add(m, sheet, {0, -40, 0});
  TriangleMesh plate = test::unit_cube();
  for (auto& v : plate.vertices) v = v.cwiseProduct(Eigen::Vector3d(10, 10, 0.5));
  add(m, plate, {-40, 0, 0});
  m.normals.assign(m.vertices.size(), Eigen::Vector3f(0, 0, 1));
  ComponentOptions f;
  f.min_thickness_mm = 0.1;
  const FilteredMesh r = filter_components(m, f);
  EXPECT_EQ(r.kept, 4);  // the three structures and the plate (2 V / A = 0.45 mm)
  ASSERT_EQ(r.dropped.size(), 1u);
  EXPECT_TRUE(r.dropped[0].thin);
  EXPECT_NEAR(r.dropped[0].centre.y(), -40, 0.5);
  EXPECT_LT(2 * r.dropped[0].volume_mm3, 0.1 * r.dropped[0].area_mm2);
  // A thickness bound above the plate's drops it too, as a sheet.
  f.min_thickness_mm = 1;
  EXPECT_EQ(filter_components(m, f).dropped.size(), 2u);
}

}  // namespace
}  // namespace mpumesh
