// The faces of each edge of a triangle set: the (edge, face) pairs sorted by the edge's
// key (edge_key) and then by face, as one run per edge, and, when asked for, a flat hash
// index from a key to its edge. Every code that walks or looks up a mesh's edges uses it:
// the topology, the dihedral angles, the triangulation's manifold checks and the
// optimiser's flips. (A flat index rather than a std::unordered_map: a node per edge
// costs more to allocate and free than the lookups it serves.)
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

class EdgeFaces {
 public:
  static constexpr size_t npos = SIZE_MAX;

  // verts_of(f): face f's three vertices. With `lookup`, find() works.
  template <class VertsOf>
  EdgeFaces(size_t faces, VertsOf verts_of, bool lookup = false) {
    std::vector<std::pair<uint64_t, uint32_t>> pairs;
    pairs.reserve(3 * faces);
    for (size_t f = 0; f < faces; ++f) {
      const auto& t = verts_of(f);
      for (size_t k = 0; k < 3; ++k) pairs.emplace_back(edge_key(t[k], t[(k + 1) % 3]), uint32_t(f));
    }
    build(std::move(pairs), lookup);
  }
  explicit EdgeFaces(const std::vector<std::array<uint32_t, 3>>& triangles, bool lookup = false)
      : EdgeFaces(triangles.size(), [&](size_t f) -> const std::array<uint32_t, 3>& { return triangles[f]; },
                  lookup) {}

  // The number of edges; their keys, ascending.
  size_t size() const { return keys_.size(); }
  const std::vector<uint64_t>& keys() const { return keys_; }
  // The faces of edge e (0 <= e < size()), ascending.
  std::span<const uint32_t> faces(size_t e) const { return {faces_.data() + first_[e], first_[e + 1] - first_[e]}; }
  // The edge with this key, or npos (built with `lookup`).
  size_t find(uint64_t key) const;
  bool contains(uint64_t key) const { return find(key) != npos; }

 private:
  void build(std::vector<std::pair<uint64_t, uint32_t>> pairs, bool lookup);
  size_t slot(uint64_t key) const;
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> first_, faces_;
  std::vector<uint32_t> index_;  // open addressing: edge number or UINT32_MAX
  size_t mask_ = 0;
};

}  // namespace mpumesh
