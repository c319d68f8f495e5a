#include "mesh/edge_edit.h"

#include <algorithm>
#include <iterator>

namespace mpumesh {

FrozenVertices FrozenVertices::renumbered(const std::vector<uint32_t>& kept) const {
  FrozenVertices out(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) out.frozen_[i] = (*this)[kept[i]];
  return out;
}

std::optional<EdgeQuad> edge_quad(const std::vector<Tri>& T, const EdgeFaces& edges, size_t e) {
  const std::span<const uint32_t> faces = edges.faces(e);
  if (faces.size() < 2) return std::nullopt;
  const uint32_t f1 = faces.front(), f2 = faces.back();
  const uint64_t key = edges.keys()[e];
  const Tri& t1 = T[f1];
  int k = 0;
  while (edge_key(t1[size_t(k)], t1[size_t((k + 1) % 3)]) != key) ++k;
  const uint32_t a = t1[size_t(k)], b = t1[size_t((k + 1) % 3)], c = t1[size_t((k + 2) % 3)];
  uint32_t d = UINT32_MAX;
  for (uint32_t v : T[f2])
    if (v != a && v != b) d = v;
  if (d == UINT32_MAX || c == d) return std::nullopt;
  return EdgeQuad{f1, f2, a, b, c, d};
}

FlipRecord flip_faces(std::vector<Tri>& T, uint32_t f1, uint32_t f2, const Tri& n1, const Tri& n2) {
  const FlipRecord undo{f1, f2, T[f1], T[f2]};
  T[f1] = n1;
  T[f2] = n2;
  return undo;
}

std::vector<uint32_t> vertex_ring(const std::vector<Tri>& T, std::span<const uint32_t> faces, uint32_t v,
                                  const std::vector<char>* gone) {
  std::vector<uint32_t> ring;
  for (uint32_t f : faces) {
    if (gone && (*gone)[f]) continue;
    for (uint32_t w : T[f])
      if (w != v) ring.push_back(w);
  }
  std::sort(ring.begin(), ring.end());
  ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  return ring;
}

std::optional<std::array<uint32_t, 2>> collapse_link(const std::vector<uint32_t>& ring_a,
                                                     const std::vector<uint32_t>& ring_b) {
  std::vector<uint32_t> shared;
  std::set_intersection(ring_a.begin(), ring_a.end(), ring_b.begin(), ring_b.end(), std::back_inserter(shared));
  if (shared.size() != 2) return std::nullopt;
  return std::array<uint32_t, 2>{shared[0], shared[1]};
}

void collapse_edge(std::vector<Tri>& T, std::span<const uint32_t> faces_of_removed, uint32_t keep, uint32_t remove,
                   std::vector<char>& gone) {
  for (uint32_t f : faces_of_removed) {
    if (gone[f]) continue;
    if (T[f][0] == keep || T[f][1] == keep || T[f][2] == keep) {
      gone[f] = 1;
      continue;
    }
    for (uint32_t& w : T[f])
      if (w == remove) w = keep;
  }
}

void drop_gone_faces(std::vector<Tri>& T, const std::vector<char>& gone) {
  size_t n = 0;
  for (size_t f = 0; f < T.size(); ++f)
    if (!gone[f]) T[n++] = T[f];
  T.resize(n);
}

}  // namespace mpumesh
