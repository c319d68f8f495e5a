// The Delaunay triangulation of a multi-material complex's points with a region per cell
// (multi/material_delaunay.h), shared by the triangulation and the trimming of its thin
// wedges (multi/thin_wedges.h). Each vertex's info is its point's index.
#pragma once

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

namespace mpumesh::multi::labelled {

using K = CGAL::Epick;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
inline constexpr int kUnlabelled = -2;
// A cell's region (kUnlabelled until its circumcentre is labelled) and, per facet, whether
// the facet's dual edge was found to pass through no third region (passes_through_third);
// a new cell starts unlabelled and unchecked.
struct CellInfo {
  int region = kUnlabelled;
  std::array<bool, 4> clear{};
};
using Cb = CGAL::Triangulation_cell_base_with_info_3<CellInfo, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Dt = CGAL::Delaunay_triangulation_3<K, Tds>;
using Point = K::Point_3;
using Cell = Dt::Cell_handle;
using Vertex = Dt::Vertex_handle;

inline Eigen::Vector3d vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// The infinite cells are the background's (region 0).
inline int region_of(const Dt& dt, Cell c) { return dt.is_infinite(c) ? 0 : c->info().region; }

// An edge as one of its cells and its two vertices' indices there, with its key
// (edge_key of the vertices' point indices).
struct EdgeRef {
  uint64_t key;
  Cell c;
  int i, j;
};

// Appends the edges of `cells`' facets between two regions (with `all`, every edge of
// `cells`) to `out`.
void add_edges(const Dt& dt, const std::vector<Cell>& cells, bool all, std::vector<EdgeRef>& out);

// `edges` in key order, each once.
void sort_unique(std::vector<EdgeRef>& edges);

// The cells around an edge, in turn.
std::vector<Cell> cells_around(const Dt& dt, const EdgeRef& e);

// The cells around v. (Finding them marks cells in the triangulation: one thread.)
std::vector<Cell> cells_at(const Dt& dt, Vertex v);

// By region r, the parts of `cells`, the cells around v: r's cells and the others', each
// split into the sets connected through the facets at v. r's boundary at v is one disc
// when each is one part.
struct Star {
  std::vector<size_t> part;  // each cell's part: the index of its part's first cell
  int in_parts = 0, out_parts = 0;
};
Star star_of(const Dt& dt, Vertex v, const std::vector<Cell>& cells, int r);

// The regions other than the background whose boundary at v is not one disc (pinched to a
// point there: two cones touching, or a layer whose two faces touch), ascending;
// `cells` the cells around v.
std::vector<int> pinched_at(const Dt& dt, Vertex v, const std::vector<Cell>& cells);

}  // namespace mpumesh::multi::labelled
