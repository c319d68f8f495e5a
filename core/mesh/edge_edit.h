// Edge edits on a closed oriented triangle mesh, shared by the mesh optimisation
// (mesh/mesh_optimize.h) and the triangulation's clean-up of thin triangles
// (mesh/thin_triangles.h): the vertices no edit may touch, an edge's quad and its flip
// (with what undoes it), and the collapse of an edge under the link condition. Each
// caller decides which edits to make; these keep the mesh a manifold when the conditions
// they state hold.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "mesh/edge_faces.h"

namespace mpumesh {

using Tri = std::array<uint32_t, 3>;

// The vertices that edits leave alone (for example those of triangles that crossed
// others after an earlier try). Default-constructed, none is frozen.
class FrozenVertices {
 public:
  FrozenVertices() = default;
  explicit FrozenVertices(size_t vertices) : frozen_(vertices, 0) {}
  bool operator[](uint32_t v) const { return !frozen_.empty() && frozen_[v]; }
  template <class Range>
  bool any_of(const Range& vertices) const {
    for (uint32_t v : vertices)
      if ((*this)[v]) return true;
    return false;
  }
  // Freezes v; true when it was not frozen yet.
  bool freeze(uint32_t v) {
    const bool was = frozen_[v];
    frozen_[v] = 1;
    return !was;
  }
  // The same vertices after a renumbering: output vertex i was input vertex kept[i].
  FrozenVertices renumbered(const std::vector<uint32_t>& kept) const;

 private:
  std::vector<char> frozen_;
};

// The two faces of an edge and its quad: f1 = abc holds the edge as a -> b, f2 = bad as
// b -> a. Flipped, ab becomes cd, with the faces adc and bcd.
struct EdgeQuad {
  uint32_t f1, f2, a, b, c, d;
  Tri flipped1() const { return {a, d, c}; }
  Tri flipped2() const { return {b, c, d}; }
  // None of its vertices frozen, and cd no edge yet (`edges` built with the lookup), so
  // that the flip keeps the mesh a manifold.
  bool may_flip(const EdgeFaces& edges, const FrozenVertices& frozen) const {
    return !frozen[a] && !frozen[b] && !frozen[c] && !frozen[d] && !edges.contains(edge_key(c, d));
  }
};
// The quad of edge e of `edges` (its first and last face); none on a border, or where c
// and d are one vertex.
std::optional<EdgeQuad> edge_quad(const std::vector<Tri>& T, const EdgeFaces& edges, size_t e);

// A flip made: the two faces and what they were.
struct FlipRecord {
  uint32_t f1, f2;
  Tri old1, old2;
};
// Replaces faces f1 and f2 by n1 and n2; returns what undoes it.
FlipRecord flip_faces(std::vector<Tri>& T, uint32_t f1, uint32_t f2, const Tri& n1, const Tri& n2);
// Undoes a flip (its faces not changed since).
inline void undo_flip(std::vector<Tri>& T, const FlipRecord& r) {
  T[r.f1] = r.old1;
  T[r.f2] = r.old2;
}

// The vertices that share a face with v, ascending, each once, over v's faces `faces`
// (those marked in `gone`, when given, left out).
std::vector<uint32_t> vertex_ring(const std::vector<Tri>& T, std::span<const uint32_t> faces, uint32_t v,
                                  const std::vector<char>* gone = nullptr);

// The link condition of the edge ab, from the rings of a and b (vertex_ring): the
// vertices adjacent to both are exactly two, the edge's opposite vertices. Returns them,
// ascending, or nothing when it fails.
std::optional<std::array<uint32_t, 2>> collapse_link(const std::vector<uint32_t>& ring_a,
                                                     const std::vector<uint32_t>& ring_b);

// Collapses the edge (keep, remove): over the faces of `remove` (`faces_of_removed`; those
// already marked in `gone` skipped), the two that hold `keep` too are marked gone and the
// others take `keep` in place of `remove`. `remove` is then used by no face. Where to put
// `keep` is the caller's.
void collapse_edge(std::vector<Tri>& T, std::span<const uint32_t> faces_of_removed, uint32_t keep, uint32_t remove,
                   std::vector<char>& gone);

// The faces not marked `gone`, in their order.
void drop_gone_faces(std::vector<Tri>& T, const std::vector<char>& gone);

}  // namespace mpumesh
