#include "multi/thin_wedges.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "geometry/triangle_mesh.h"

namespace mpumesh::multi {
namespace {

using namespace labelled;

// Cells of one region in turn around an edge: `count` of them from `first` in the ring,
// their dihedral angles at the edge adding up to `angle` (radians; infinite where one is
// an infinite cell).
struct Run {
  int region;
  size_t first, count;
  double angle;
};

// The dihedral angle of cell c at its edge (a, b) (vertex infos).
double dihedral_at(const Dt& dt, Cell c, uint32_t a, uint32_t b, const std::vector<Eigen::Vector3d>& pts) {
  if (dt.is_infinite(c)) return INFINITY;
  std::array<uint32_t, 2> other{};
  int n = 0;
  for (int k = 0; k < 4; ++k)
    if (const uint32_t v = c->vertex(k)->info(); v != a && v != b) other[size_t(n++)] = v;
  const Eigen::Vector3d e = (pts[b] - pts[a]).normalized();
  Eigen::Vector3d u = pts[other[0]] - pts[a], w = pts[other[1]] - pts[a];
  u -= e * e.dot(u);
  w -= e * e.dot(w);
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

// The runs of regions around the edge, in turn (none where one region holds every cell).
std::vector<Run> runs_around(const Dt& dt, const EdgeRef& e, const std::vector<Cell>& ring,
                             const std::vector<Eigen::Vector3d>& pts) {
  const size_t n = ring.size();
  size_t start = n;
  for (size_t k = 0; k < n && start == n; ++k)
    if (region_of(dt, ring[k]) != region_of(dt, ring[(k + n - 1) % n])) start = k;
  std::vector<Run> runs;
  if (start == n) return runs;
  const uint32_t a = e.c->vertex(e.i)->info(), b = e.c->vertex(e.j)->info();
  for (size_t m = 0; m < n; ++m) {
    const size_t k = (start + m) % n;
    const int r = region_of(dt, ring[k]);
    if (runs.empty() || runs.back().region != r) runs.push_back({r, k, 0, 0});
    ++runs.back().count;
    runs.back().angle += dihedral_at(dt, ring[k], a, b, pts);
  }
  return runs;
}

// Whether no region's cells make more than one run around the edge.
bool manifold_at_edge(const Dt& dt, const EdgeRef& e) {
  const std::vector<Cell> ring = cells_around(dt, e);
  std::vector<int> run_regions;  // a run's region where it starts
  for (size_t k = 0; k < ring.size(); ++k)
    if (const int r = region_of(dt, ring[k]); r != region_of(dt, ring[(k + ring.size() - 1) % ring.size()]))
      run_regions.push_back(r);
  std::sort(run_regions.begin(), run_regions.end());
  return std::adjacent_find(run_regions.begin(), run_regions.end()) == run_regions.end();
}

// Whether region r's boundary at v is one disc.
bool one_disc_at(const Dt& dt, Vertex v, int r) {
  const Star st = star_of(dt, v, cells_at(dt, v), r);
  return st.in_parts <= 1 && st.out_parts <= 1;
}

// Cells to give from one region to another.
struct Change {
  std::vector<Cell> cells;
  int from, to;
};

// For the thinnest run at the edge under `min_angle` of a region other than the background
// that has no other run there, the changes that widen or remove it, in order of
// preference: the run given to the neighbouring run's region that fills more of the turn
// (the lower region on a tie), or to the other neighbour's; else the neighbouring runs'
// cells next to it given to its region. None when there is no such run.
std::vector<Change> thin_run_changes(const Dt& dt, const EdgeRef& e, const std::vector<Eigen::Vector3d>& pts,
                                     double min_angle) {
  const std::vector<Cell> ring = cells_around(dt, e);
  const std::vector<Run> runs = runs_around(dt, e, ring, pts);
  const size_t n = runs.size();
  std::optional<size_t> thinnest;
  for (size_t k = 0; k < n; ++k) {
    const Run& r = runs[k];
    if (r.region == 0 || r.angle >= min_angle) continue;
    if (std::count_if(runs.begin(), runs.end(), [&](const Run& x) { return x.region == r.region; }) != 1) continue;
    if (!thinnest || r.angle < runs[*thinnest].angle) thinnest = k;
  }
  if (!thinnest) return {};
  const Run &r = runs[*thinnest], &prev = runs[(*thinnest + n - 1) % n], &next = runs[(*thinnest + 1) % n];
  std::vector<Cell> cells;
  for (size_t m = 0; m < r.count; ++m) cells.push_back(ring[(r.first + m) % ring.size()]);
  std::vector<Change> out = {{cells, r.region, prev.region}, {cells, r.region, next.region}};
  if (next.angle > prev.angle || (next.angle == prev.angle && next.region < prev.region)) std::swap(out[0], out[1]);
  if (prev.region == next.region) out.pop_back();
  const Cell before = ring[(r.first + ring.size() - 1) % ring.size()], after = ring[(r.first + r.count) % ring.size()];
  for (const Cell c : {before, after})
    if (!dt.is_infinite(c)) out.push_back({{c}, region_of(dt, c), r.region});
  return out;
}

// The change made where every region's boundary stays a closed manifold; whether it was.
bool apply(Dt& dt, const Change& t) {
  for (const Cell c : t.cells) c->info().region = t.to;
  bool ok = true;
  for (size_t k = 0; k < t.cells.size() && ok; ++k) {
    const Cell c = t.cells[k];
    for (int a = 0; a < 4 && ok; ++a) {
      ok = one_disc_at(dt, c->vertex(a), t.from) && one_disc_at(dt, c->vertex(a), t.to);
      for (int b = a + 1; b < 4 && ok; ++b)
        ok = manifold_at_edge(dt, {edge_key(c->vertex(a)->info(), c->vertex(b)->info()), c, a, b});
    }
  }
  if (!ok)
    for (const Cell c : t.cells) c->info().region = t.from;
  return ok;
}

}  // namespace

WedgeTrimStats trim_thin_wedges(Dt& dt, const std::vector<Eigen::Vector3d>& pts, double min_wedge_deg,
                                int max_rounds) {
  const double min_angle = min_wedge_deg * std::numbers::pi / 180;
  WedgeTrimStats st;
  std::vector<Cell> cells;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) cells.push_back(c);
  std::vector<EdgeRef> edges;
  add_edges(dt, cells, false, edges);
  for (int round = 0; round < max_rounds && !edges.empty(); ++round) {
    sort_unique(edges);
    // Where a thin run is: found in parallel (circulating around an edge reads only), then
    // each edge's decided again and applied in key order, since an earlier one may change it.
    std::vector<char> thin(edges.size(), 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, edges.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k) thin[k] = !thin_run_changes(dt, edges[k], pts, min_angle).empty();
    });
    std::vector<Cell> changed;
    for (size_t k = 0; k < edges.size(); ++k) {
      if (!thin[k]) continue;
      for (const Change& t : thin_run_changes(dt, edges[k], pts, min_angle))
        if (apply(dt, t)) {
          changed.insert(changed.end(), t.cells.begin(), t.cells.end());
          break;
        }
    }
    if (changed.empty()) break;
    ++st.rounds;
    st.cells += int64_t(changed.size());
    edges.clear();
    add_edges(dt, changed, true, edges);
  }
  return st;
}

}  // namespace mpumesh::multi
