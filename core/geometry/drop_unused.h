// Dropping the points that no cell uses, for meshes whose cells index a point list.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mpumesh {

// Removes the points that no cell of `cells` uses, keeping the others' order, and
// renumbers `cells` and every list in `more` (such as a volume mesh's boundary
// triangles, whose points its tetrahedra use). Returns the old index of each point kept.
template <class Point, std::size_t N, class... More>
std::vector<uint32_t> drop_unused_points(std::vector<Point>& points, std::vector<std::array<uint32_t, N>>& cells, More&... more) {
  std::vector<uint32_t> index(points.size(), UINT32_MAX);
  for (const auto& c : cells)
    for (uint32_t v : c) index[v] = 0;
  uint32_t n = 0;
  std::vector<uint32_t> kept;
  for (std::size_t i = 0; i < index.size(); ++i)
    if (index[i] == 0) points[n] = points[i], index[i] = n++, kept.push_back(uint32_t(i));
  points.resize(n);
  const auto renumber = [&](auto& list) {
    for (auto& c : list)
      for (uint32_t& v : c) v = index[v];
  };
  renumber(cells);
  (renumber(more), ...);
  return kept;
}

}  // namespace mpumesh
