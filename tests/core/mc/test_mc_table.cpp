// The generated marching-cubes table: every case closes, triangles face away from the
// inside corners, and random binary volumes always give closed, oriented 2-manifolds.
#include <gtest/gtest.h>

#include "cpu/cpu_backend.h"
#include "mc/marching_cubes.h"
#include "mc/mc_table.h"
#include "mesh/topology.h"
#include "test_support.h"

namespace mpumesh {
namespace {

Eigen::Vector3d edge_mid(int e) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int c : mc::kEdgeCorners[size_t(e)])
    p += 0.5 * Eigen::Vector3d(mc::kCorner[size_t(c)][0], mc::kCorner[size_t(c)][1], mc::kCorner[size_t(c)][2]);
  return p;
}

TEST(McTable, EmptyAndFullCubesHaveNoTriangles) {
  EXPECT_EQ(mc::case_table()[0].triangle_count, 0);
  EXPECT_EQ(mc::case_table()[255].triangle_count, 0);
}

TEST(McTable, TrianglesUseOnlyCrossingEdgesAndCoverEachOnce) {
  for (int c = 0; c < 256; ++c) {
    const auto& cc = mc::case_table()[size_t(c)];
    std::array<int, 12> uses{};
    for (int s = 0; s < 3 * cc.triangle_count; ++s) ++uses[size_t(cc.edges[size_t(s)])];
    for (int e = 0; e < 12; ++e) {
      const auto [a, b] = mc::kEdgeCorners[size_t(e)];
      const bool crossing = ((c >> a) & 1) != ((c >> b) & 1);
      EXPECT_EQ(crossing, uses[size_t(e)] > 0) << "case " << c << " edge " << e;
    }
  }
}

TEST(McTable, SingleInsideCornerTriangleFacesAway) {
  for (int corner = 0; corner < 8; ++corner) {
    const auto& cc = mc::case_table()[size_t(1 << corner)];
    ASSERT_EQ(cc.triangle_count, 1);
    const Eigen::Vector3d a = edge_mid(cc.edges[0]), b = edge_mid(cc.edges[1]), c = edge_mid(cc.edges[2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const Eigen::Vector3d p(mc::kCorner[size_t(corner)][0], mc::kCorner[size_t(corner)][1],
                            mc::kCorner[size_t(corner)][2]);
    EXPECT_LT(n.dot(p - a), 0) << "normal must point away from the inside corner " << corner;
  }
}

TEST(McTable, AmbiguousFaceSeparatesInsideCorners) {
  // Corners 0 and 2 inside (diagonal on the bottom face): two separate triangles.
  EXPECT_EQ(mc::case_table()[0b00000101].triangle_count, 2);
  // Body diagonal 0 and 6: two triangles.
  EXPECT_EQ(mc::case_table()[0b01000001].triangle_count, 2);
}

TEST(McTable, RandomVolumesGiveClosedOrientedManifolds) {
  CpuBackend cpu;
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    const double fill = 0.2 + 0.6 * double(seed % 7) / 6.0;
    const Volume v = test::random_volume({9, 8, 7}, fill, seed);
    const TriangleMesh m = marching_cubes(v, {0.0}, cpu);
    const Topology t = analyze_topology(m);
    ASSERT_TRUE(t.closed) << "seed " << seed << ": " << t.border_edges << " border edges";
    ASSERT_TRUE(t.manifold) << "seed " << seed << ": " << t.nonmanifold_edges << " edges, "
                            << t.nonmanifold_vertices << " vertices";
    ASSERT_TRUE(t.oriented) << "seed " << seed;
  }
}

}  // namespace
}  // namespace mpumesh
