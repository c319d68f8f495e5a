// The refill of slivers' cavities on a hand-built mesh: a tent of two triangles over a
// diamond, closed below by an apex. The tent's top edge and the diamond's diagonal make a
// sliver of four boundary nodes; the two tetrahedra under it join the diamond to the apex.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "tet/sliver_cavities.h"
#include "tet/tet_quality.h"

namespace mpumesh {
namespace {

double volume(const TetMesh& m, const std::array<uint32_t, 4>& t) {
  const auto& p = m.nodes;
  return (p[t[1]] - p[t[0]]).dot((p[t[2]] - p[t[0]]).cross(p[t[3]] - p[t[0]])) / 6;
}

double min_dihedral(const TetMesh& m) { return measure_tet_quality(m).min_dihedral_deg; }

std::set<std::array<uint32_t, 3>> faces_of_tets(const TetMesh& m) {
  std::set<std::array<uint32_t, 3>> s;
  for (const auto& t : m.tets)
    for (const auto& f : kTetFace) {
      std::array<uint32_t, 3> k = {t[size_t(f[0])], t[size_t(f[1])], t[size_t(f[2])]};
      std::ranges::sort(k);
      s.insert(k);
    }
  return s;
}

// Nodes a, b (the tent's top edge, `rise` above), c, d (the diamond's diagonal), e (the
// apex); the sliver abcd in region 1, the two under it in `below`.
TetMesh tent(double rise, int32_t below) {
  TetMesh m;
  m.nodes = {{-1, 0, rise}, {1, 0, rise}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1.2}};
  m.tets = {{0, 1, 2, 3}, {0, 2, 3, 4}, {1, 2, 3, 4}};
  m.region = {1, below, below};
  for (auto& t : m.tets)
    if (volume(m, t) < 0) std::swap(t[2], t[3]);
  m.boundary = {{0, 1, 2}, {0, 1, 3}, {0, 2, 4}, {0, 3, 4}, {1, 2, 4}, {1, 3, 4}};
  if (below != 1) m.boundary.push_back({0, 2, 3}), m.boundary.push_back({1, 2, 3});
  m.boundary_region.assign(m.boundary.size(), 1);
  m.regions = below == 1 ? 1 : 2;
  return m;
}

TEST(SliverCavities, RefillsASliverOfBoundaryNodesWithItsNeighbours) {
  TetMesh m = tent(0.1, 1);
  const TetQuality before = measure_tet_quality(m);
  ASSERT_LT(before.min_dihedral_deg, 10);
  EXPECT_EQ(refill_sliver_cavities(m, 10), 1);
  const TetQuality after = measure_tet_quality(m);
  std::printf("smallest dihedral %.2f -> %.2f deg, %zu tetrahedra\n", before.min_dihedral_deg, after.min_dihedral_deg,
              m.tets.size());
  EXPECT_GE(after.min_dihedral_deg, 10);
  EXPECT_EQ(m.tets.size(), 6u);  // the new node joined to the cavity's six faces
  EXPECT_EQ(m.region.size(), m.tets.size());
  EXPECT_EQ(after.inverted, 0);
  EXPECT_NEAR(after.volume_mm3, before.volume_mm3, 1e-12);
  const auto faces = faces_of_tets(m);
  for (auto f : m.boundary) {
    std::ranges::sort(f);
    EXPECT_TRUE(faces.count(f)) << "a boundary triangle is no longer a face";
  }
}

TEST(SliverCavities, NeverCrossesAFaceBetweenRegions) {
  // The neighbours in another region: the sliver alone is its cavity, and no node inside
  // it makes tetrahedra better than the sliver, so nothing changes.
  TetMesh m = tent(0.1, 2);
  ASSERT_LT(min_dihedral(m), 10);
  const TetMesh before = m;
  EXPECT_EQ(refill_sliver_cavities(m, 10), 0);
  EXPECT_EQ(m.tets, before.tets);
  EXPECT_EQ(m.nodes.size(), before.nodes.size());
}

TEST(SliverCavities, LeavesGoodTetrahedraAlone) {
  TetMesh m = tent(0.8, 1);
  ASSERT_GE(min_dihedral(m), 10);
  const TetMesh before = m;
  EXPECT_EQ(refill_sliver_cavities(m, 10), 0);
  EXPECT_EQ(m.tets, before.tets);
}

}  // namespace
}  // namespace mpumesh
