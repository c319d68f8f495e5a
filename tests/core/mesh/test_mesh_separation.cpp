// mesh/mesh_separation: a closed mesh moved out of another that it crosses.
#include <gtest/gtest.h>

#include "mesh/cgal_geometry.h"
#include "mesh/mesh_separation.h"
#include "mesh/topology.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// Two spheres that overlap by 1 mm: the second yields, and neither crosses the other after.
TEST(MeshSeparation, MovesTheLaterMeshOutOfTheFixedOneWithoutFoldingIt) {
  const TriangleMesh fixed = test::icosphere(5.0, 3);
  TriangleMesh later = test::icosphere(5.0, 3);
  for (auto& v : later.vertices) v.x() += 9.0;
  ASSERT_GT(count_crossings(later, fixed), 0);
  const SeparationStats s = separate_from(later, {&fixed}, 0.1);
  EXPECT_GT(s.crossings_before, 0);
  EXPECT_EQ(s.crossings_after, 0);
  EXPECT_EQ(count_crossings(later, fixed), 0);
  EXPECT_GT(s.moved_vertices, 0);
  EXPECT_LT(s.max_move_mm, 1.5);
  EXPECT_EQ(count_self_intersections(later), 0);
  const Topology t = analyze_topology(later);
  EXPECT_TRUE(t.closed && t.oriented);
  // Only the vertices in and next to the overlap (x < 5) moved.
  const TriangleMesh start = test::icosphere(5.0, 3);
  for (size_t i = 0; i < later.vertices.size(); ++i) {
    const Eigen::Vector3d orig = start.vertices[i] + Eigen::Vector3d(9, 0, 0);
    if (orig.x() > 6.5) EXPECT_EQ(later.vertices[i], orig) << i;
  }
}

TEST(MeshSeparation, LeavesAMeshThatCrossesNothingAlone) {
  const TriangleMesh fixed = test::icosphere(5.0, 2);
  TriangleMesh later = test::icosphere(5.0, 2);
  for (auto& v : later.vertices) v.x() += 10.5;
  const TriangleMesh before = later;
  const SeparationStats s = separate_from(later, {&fixed}, 0.1);
  EXPECT_EQ(s.crossings_before, 0);
  EXPECT_EQ(s.moved_vertices, 0);
  EXPECT_EQ(later.vertices, before.vertices);
}

}  // namespace
}  // namespace mpumesh
