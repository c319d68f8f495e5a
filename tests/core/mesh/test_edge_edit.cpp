// The edge edits (core/mesh/edge_edit.h) on an octahedron and an icosphere: a quad and its
// flip and undo, the link condition, a collapse that keeps the mesh a closed manifold, and
// frozen vertices.
#include <gtest/gtest.h>

#include <algorithm>

#include "geometry/vertex_faces.h"
#include "mesh/edge_edit.h"
#include "mesh/topology.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(EdgeEdit, AQuadFlipsAndTheFlipUndoes) {
  const TriangleMesh ico = test::icosphere(10, 1);
  std::vector<Tri> T = ico.triangles;
  const EdgeFaces edges(T, true);
  const auto q = edge_quad(T, edges, 0);
  ASSERT_TRUE(q);
  // f1 runs a -> b, f2 b -> a; c and d their third vertices.
  const Tri &t1 = T[q->f1], &t2 = T[q->f2];
  auto runs = [](const Tri& t, uint32_t a, uint32_t b) {
    for (size_t k = 0; k < 3; ++k)
      if (t[k] == a && t[(k + 1) % 3] == b) return true;
    return false;
  };
  EXPECT_TRUE(runs(t1, q->a, q->b));
  EXPECT_TRUE(runs(t2, q->b, q->a));
  EXPECT_TRUE(q->may_flip(edges, FrozenVertices()));
  FrozenVertices frozen(ico.vertices.size());
  EXPECT_TRUE(frozen.freeze(q->c));
  EXPECT_FALSE(frozen.freeze(q->c));
  EXPECT_FALSE(q->may_flip(edges, frozen));
  const std::vector<Tri> before = T;
  const FlipRecord rec = flip_faces(T, q->f1, q->f2, q->flipped1(), q->flipped2());
  TriangleMesh flipped = ico;
  flipped.triangles = T;
  const Topology t = analyze_topology(flipped);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_TRUE(EdgeFaces(T, true).contains(edge_key(q->c, q->d)));
  EXPECT_FALSE(EdgeFaces(T, true).contains(edge_key(q->a, q->b)));
  undo_flip(T, rec);
  EXPECT_EQ(T, before);
}

TEST(EdgeEdit, ACollapseUnderTheLinkConditionKeepsAClosedManifold) {
  TriangleMesh m = test::icosphere(10, 2);
  const VertexFaces vf = vertex_faces(m);
  const Tri t0 = m.triangles[0];
  const uint32_t keep = t0[0], remove = t0[1];
  const auto link = collapse_link(vertex_ring(m.triangles, vf[keep], keep), vertex_ring(m.triangles, vf[remove], remove));
  ASSERT_TRUE(link);
  EXPECT_NE((*link)[0], (*link)[1]);
  std::vector<char> gone(m.triangles.size(), 0);
  collapse_edge(m.triangles, vf[remove], keep, remove, gone);
  EXPECT_EQ(std::count(gone.begin(), gone.end(), 1), 2);
  drop_gone_faces(m.triangles, gone);
  for (const Tri& t : m.triangles)
    for (uint32_t v : t) EXPECT_NE(v, remove);
  const Topology t = analyze_topology(m);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_EQ(t.genus, 0);
  // On a triangular bipyramid the ends of an equator edge share three neighbours (the
  // third equator vertex and both poles): the collapse would pinch, and the link
  // condition fails.
  const std::vector<Tri> bi = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {1, 0, 4}, {2, 1, 4}, {0, 2, 4}};
  const VertexFaces bv = vertex_faces(5, bi.size(), [&](size_t f) { return bi[f]; });
  EXPECT_FALSE(collapse_link(vertex_ring(bi, bv[0], 0), vertex_ring(bi, bv[1], 1)));
}

}  // namespace
}  // namespace mpumesh
