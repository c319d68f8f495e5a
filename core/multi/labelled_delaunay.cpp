#include "multi/labelled_delaunay.h"

#include <algorithm>
#include <optional>

#include "geometry/triangle_mesh.h"

namespace mpumesh::multi::labelled {

void add_edges(const Dt& dt, const std::vector<Cell>& cells, bool all, std::vector<EdgeRef>& out) {
  for (const Cell c : cells)
    for (int i = 0; i < 4; ++i) {
      if (!all && region_of(dt, c) == region_of(dt, c->neighbor(i))) continue;
      for (int m = 1; m < 4; ++m)
        for (int n = m + 1; n < 4; ++n) {
          const int a = (i + m) & 3, b = (i + n) & 3;
          out.push_back({edge_key(c->vertex(a)->info(), c->vertex(b)->info()), c, a, b});
        }
    }
}

void sort_unique(std::vector<EdgeRef>& edges) {
  std::sort(edges.begin(), edges.end(), [](const EdgeRef& x, const EdgeRef& y) { return x.key < y.key; });
  edges.erase(std::unique(edges.begin(), edges.end(), [](const EdgeRef& x, const EdgeRef& y) { return x.key == y.key; }),
              edges.end());
}

std::vector<Cell> cells_around(const Dt& dt, const EdgeRef& e) {
  std::vector<Cell> ring;
  Dt::Cell_circulator cc = dt.incident_cells(e.c, e.i, e.j), done = cc;
  do ring.push_back(cc);
  while (++cc != done);
  return ring;
}

std::vector<Cell> cells_at(const Dt& dt, Vertex v) {
  std::vector<Cell> cells;
  dt.incident_cells(v, std::back_inserter(cells));
  return cells;
}

Star star_of(const Dt& dt, Vertex v, const std::vector<Cell>& cells, int r) {
  Star st;
  std::vector<size_t> order(cells.size());  // the cells by handle, to find a neighbour
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return cells[a] < cells[b]; });
  auto index_of = [&](Cell c) -> std::optional<size_t> {
    const auto it = std::lower_bound(order.begin(), order.end(), c, [&](size_t k, Cell x) { return cells[k] < x; });
    if (it == order.end() || cells[*it] != c) return std::nullopt;
    return *it;
  };
  st.part.assign(cells.size(), SIZE_MAX);
  for (size_t s = 0; s < cells.size(); ++s) {
    if (st.part[s] != SIZE_MAX) continue;
    const bool in = region_of(dt, cells[s]) == r;
    ++(in ? st.in_parts : st.out_parts);
    std::vector<size_t> stack = {s};
    st.part[s] = s;
    while (!stack.empty()) {
      const Cell c = cells[stack.back()];
      stack.pop_back();
      for (int k = 0; k < 4; ++k) {
        if (c->vertex(k) == v) continue;
        const std::optional<size_t> t = index_of(c->neighbor(k));
        if (!t || st.part[*t] != SIZE_MAX || (region_of(dt, cells[*t]) == r) != in) continue;
        st.part[*t] = s;
        stack.push_back(*t);
      }
    }
  }
  return st;
}

std::vector<int> pinched_at(const Dt& dt, Vertex v, const std::vector<Cell>& cells) {
  std::vector<int> regions;
  for (const Cell c : cells) regions.push_back(region_of(dt, c));
  std::sort(regions.begin(), regions.end());
  regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
  std::vector<int> out;
  if (regions.size() < 2) return out;
  for (const int r : regions) {
    if (r == 0) continue;
    const Star st = star_of(dt, v, cells, r);
    if (st.in_parts > 1 || st.out_parts > 1) out.push_back(r);
  }
  return out;
}

}  // namespace mpumesh::multi::labelled
