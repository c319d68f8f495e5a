#include "mesh/spurious_components.h"

#include <numeric>

namespace mpumesh {

std::vector<char> sampled_components(const std::vector<std::array<uint32_t, 3>>& triangles, size_t vertices,
                                     const std::function<bool(uint32_t)>& sampled, int64_t* unsampled,
                                     const std::function<bool(uint32_t)>& off) {
  std::vector<uint32_t> parent(vertices);  // union-find over the vertices
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const auto& t : triangles)
    for (int k = 1; k < 3; ++k) parent[find(t[size_t(k)])] = find(t[0]);
  std::vector<char> held(vertices, 0);  // per component root: holds a sampled vertex
  std::vector<char> seen(vertices, 0);
  // Per component root: its vertices, and those off the sample (each vertex counted once).
  std::vector<uint32_t> size(vertices, 0), away(vertices, 0);
  for (const auto& t : triangles)
    for (uint32_t v : t) {
      const uint32_t r = find(v);
      held[r] |= char(sampled(v));
      if (seen[v]) continue;
      seen[v] = 1;
      ++size[r];
      away[r] += off && off(v);
    }
  std::fill(seen.begin(), seen.end(), 0);
  std::vector<char> keep(triangles.size());
  int64_t none = 0;
  for (size_t f = 0; f < triangles.size(); ++f) {
    const uint32_t r = find(triangles[f][0]);
    keep[f] = held[r] && 2 * away[r] < size[r];
    none += !keep[f] && !seen[r];
    seen[r] = 1;
  }
  if (unsampled) *unsampled = none;
  return keep;
}

}  // namespace mpumesh
