// The faces of each edge (core/mesh/edge_faces.h): the runs in key order, the faces in
// order, the lookup, on a closed mesh, an open one and a non-manifold one.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "mesh/edge_faces.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// The (edge -> faces) map the structure must hold, by brute force.
std::map<uint64_t, std::vector<uint32_t>> brute(const std::vector<std::array<uint32_t, 3>>& T) {
  std::map<uint64_t, std::vector<uint32_t>> m;
  for (uint32_t f = 0; f < T.size(); ++f)
    for (size_t k = 0; k < 3; ++k) m[edge_key(T[f][k], T[f][(k + 1) % 3])].push_back(f);
  return m;
}

void expect_matches(const std::vector<std::array<uint32_t, 3>>& T) {
  const EdgeFaces e(T, true);
  const auto want = brute(T);
  ASSERT_EQ(e.size(), want.size());
  size_t i = 0;
  for (const auto& [key, faces] : want) {
    EXPECT_EQ(e.keys()[i], key);
    const auto got = e.faces(i);
    EXPECT_EQ(std::vector<uint32_t>(got.begin(), got.end()), faces);
    EXPECT_EQ(e.find(key), i);
    ++i;
  }
  EXPECT_EQ(e.find(edge_key(1000000, 1000001)), EdgeFaces::npos);
  EXPECT_FALSE(e.contains(edge_key(1000000, 1000001)));
}

TEST(EdgeFaces, HoldsEveryEdgesFacesInOrder) {
  const TriangleMesh ico = test::icosphere(10, 2);
  expect_matches(ico.triangles);
  const EdgeFaces e(ico.triangles);
  EXPECT_EQ(e.size(), ico.triangles.size() * 3 / 2);  // closed: two faces an edge
  for (size_t i = 0; i < e.size(); ++i) EXPECT_EQ(e.faces(i).size(), 2u);
  TriangleMesh open = ico;
  open.triangles.pop_back();
  expect_matches(open.triangles);
  // Three faces on one edge (0, 1).
  expect_matches({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {2, 1, 3}});
  expect_matches({});
}

}  // namespace
}  // namespace mpumesh
