// The components of a triangulation that particles hold, and those mostly off the sample.
#include <gtest/gtest.h>

#include "mesh/spurious_components.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// Components of a triangle list that hold a sampled vertex: two tetrahedra (vertices 0-3
// and 4-7) and a third joined to the second through vertex 7 (7-10). Only vertex 1 and
// vertex 9 are sampled: the first and the joined pair stay, nothing else is removed. Then
// the components with more than half of their vertices off the sample go too.
TEST(RestrictedDelaunay, KeepsTheComponentsThatParticlesHold) {
  auto tet = [](uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    return std::vector<std::array<uint32_t, 3>>{{a, b, c}, {a, d, b}, {b, d, c}, {a, c, d}};
  };
  std::vector<std::array<uint32_t, 3>> tris;
  for (const auto& t : {tet(0, 1, 2, 3), tet(4, 5, 6, 7), tet(7, 8, 9, 10), tet(11, 12, 13, 14)})
    tris.insert(tris.end(), t.begin(), t.end());
  int64_t unsampled = -1;
  const std::vector<char> keep =
      sampled_components(tris, 15, [](uint32_t v) { return v == 1 || v == 9; }, &unsampled);
  const std::vector<char> want = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0};
  EXPECT_EQ(keep, want);
  EXPECT_EQ(unsampled, 1);
  EXPECT_EQ(std::count(keep.begin(), keep.end(), 1), 12);
  sampled_components(tris, 15, [](uint32_t) { return false; }, &unsampled);
  EXPECT_EQ(unsampled, 3);
  // Off the sample: the first tetrahedron with one of its four vertices off stays (under
  // half); the joined pair, 7 vertices with 4 off (4, 5, 6, 8), goes although vertex 9 is
  // sampled.
  const std::vector<char> keep_off = sampled_components(
      tris, 15, [](uint32_t v) { return v == 1 || v == 9; }, &unsampled,
      [](uint32_t v) { return v == 2 || v == 4 || v == 5 || v == 6 || v == 8; });
  const std::vector<char> want_off = {1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(keep_off, want_off);
  EXPECT_EQ(unsampled, 2);
}

}  // namespace
}  // namespace mpumesh
