#include "multi/labelled_delaunay.h"

#include <algorithm>

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

}  // namespace mpumesh::multi::labelled
