#include "multi/material_delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <unordered_map>

#include "common/error.h"
#include "mesh/circumcentre.h"

namespace mpumesh::multi {
namespace {

using K = CGAL::Epick;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
constexpr int kUnlabelled = -2;
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
constexpr int kMaxRounds = 40;

Eigen::Vector3d vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// The circumcentre from the vertices in id order (the same bits whichever order the cell
// lists them in).
Eigen::Vector3d centre(Cell c) {
  std::array<Dt::Vertex_handle, 4> v = {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a->info() < b->info(); });
  return robust_circumcentre(vec(v[0]->point()), vec(v[1]->point()), vec(v[2]->point()), vec(v[3]->point()));
}

int region_of(const Dt& dt, Cell c) { return dt.is_infinite(c) ? 0 : c->info().region; }

void label_new_cells(const MaterialField& field, Dt& dt) {
  std::vector<Cell> todo;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
    if (c->info().region == kUnlabelled) todo.push_back(c);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, todo.size(), 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) todo[k]->info().region = field.region_at(centre(todo[k]));
  });
}

struct Facet {
  Cell cell;  // the lower region's side
  int i;
  std::array<uint32_t, 3> v;  // normal out of `cell`
  std::array<int, 2> regions;
};

// Each facet between two regions once, from the lower region's side (the background's
// side of a facet on the hull is the infinite cell, seen from the finite one).
std::vector<Facet> complex_facets(const Dt& dt) {
  const auto orientation = dt.geom_traits().orientation_3_object();
  std::vector<Facet> out;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    const int rc = c->info().region;
    for (int i = 0; i < 4; ++i) {
      const Cell n = c->neighbor(i);
      const bool hull = dt.is_infinite(n);
      const int rn = region_of(dt, n);
      if (hull ? rc == 0 : rc >= rn) continue;
      auto a = c->vertex((i + 1) & 3), b = c->vertex((i + 2) & 3), d = c->vertex((i + 3) & 3);
      if (orientation(a->point(), b->point(), d->point(), c->vertex(i)->point()) == CGAL::POSITIVE) std::swap(b, d);
      if (hull) out.push_back({c, i, {a->info(), d->info(), b->info()}, {0, rc}});  // into c
      else out.push_back({c, i, {a->info(), b->info(), d->info()}, {rc, rn}});      // out of c
    }
  }
  return out;
}

struct EdgeUse {
  int count = 0, balance = 0;  // facets, and their directions (+1 a->b, -1 b->a) summed
  size_t widest = SIZE_MAX;
  double area = -1;
};

// Region r's boundary edges with other than two facets or an unbalanced orientation, each
// with its widest facet.
std::vector<size_t> defective_facets(const std::vector<Facet>& facets, const std::vector<Eigen::Vector3d>& pts,
                                     int regions, int64_t* defects) {
  std::vector<size_t> out;
  int64_t n = 0;
  for (int r = 0; r < regions; ++r) {
    std::unordered_map<uint64_t, EdgeUse> edges;
    for (size_t f = 0; f < facets.size(); ++f) {
      const Facet& F = facets[f];
      if (F.regions[0] != r && F.regions[1] != r) continue;
      const double area = (pts[F.v[1]] - pts[F.v[0]]).cross(pts[F.v[2]] - pts[F.v[0]]).norm();
      const int sign = F.regions[0] == r ? 1 : -1;
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = F.v[size_t(k)], b = F.v[size_t((k + 1) % 3)];
        EdgeUse& e = edges[edge_key(a, b)];
        ++e.count;
        e.balance += (a < b ? 1 : -1) * sign;
        if (area > e.area) {
          e.area = area;
          e.widest = f;
        }
      }
    }
    for (const auto& [key, e] : edges)
      if (e.count != 2 || e.balance != 0) {
        ++n;
        out.push_back(e.widest);
      }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (defects) *defects = n;
  return out;
}

// An end of a facet's dual Voronoi edge in cell c, `other` the cell across the facet: c's
// circumcentre or, for the infinite cell beyond a facet of the convex hull, a point on
// the dual ray from other's circumcentre out through the facet, four facet sizes beyond
// the facet and that circumcentre, where the infinite cells' region (the background)
// lies.
Eigen::Vector3d dual_end(const Dt& dt, Cell c, Cell other) {
  if (!dt.is_infinite(c)) return centre(c);
  const int k = other->index(c);  // other's vertex opposite the facet
  const Eigen::Vector3d apex = vec(other->vertex(k)->point()), a = vec(other->vertex((k + 1) & 3)->point()),
                        b = vec(other->vertex((k + 2) & 3)->point()), d = vec(other->vertex((k + 3) & 3)->point());
  Eigen::Vector3d n = (b - a).cross(d - a);
  if (n.dot(a - apex) < 0) n = -n;
  n.normalize();
  const Eigen::Vector3d from = centre(other), mid = (a + b + d) / 3;
  const double size = std::max({(b - a).norm(), (d - a).norm(), (d - b).norm()});
  return from + n * (std::max(0.0, n.dot(mid - from)) + 4 * size);
}

// Where the labelling changes along the facet's dual Voronoi edge, first from the lower
// region's side (from the higher's with `from_higher`), on the interface of the two regions
// met there; false when none is found.
bool dual_crossing(const MaterialField& field, const Dt& dt, const Facet& F, Eigen::Vector3d& x,
                   bool from_higher = false) {
  Cell near = F.cell, far = F.cell->neighbor(F.i);
  if (dt.is_infinite(near) && dt.is_infinite(far)) return false;
  if (from_higher) std::swap(near, far);
  const Eigen::Vector3d near_end = dual_end(dt, near, far), far_end = dual_end(dt, far, near);
  Eigen::Vector3d lo = near_end, hi = far_end;
  const int r0 = field.region_at(lo);
  if (field.region_at(hi) == r0) return false;
  for (int it = 0; it < 40; ++it) {
    const Eigen::Vector3d mid = 0.5 * (lo + hi);
    (field.region_at(mid) == r0 ? lo : hi) = mid;
  }
  const int r1 = field.region_at(hi);
  x = 0.5 * (lo + hi);
  const double reach = std::max((hi - lo).norm(), 0.25 * (near_end - far_end).norm());
  Eigen::Vector3d p = x;
  if (field.project_interface(p, std::min(r0, r1), std::max(r0, r1), reach)) x = p;
  return true;
}

// Whether a region other than a and b holds a point of the segment p-q: its value there
// below both of theirs. The functions are about signed distances (slope 1), so the
// margin by which a and b beat every other region changes by at most twice the distance
// moved: a segment whose middle has a margin above its length holds no other region;
// otherwise both halves are searched, down to a thousandth of a millimetre.
bool third_on_segment(const MaterialField& field, const Eigen::Vector3d& p, const Eigen::Vector3d& q, int a, int b,
                      std::vector<double>& f) {
  const double length = (q - p).norm();
  const Eigen::Vector3d mid = 0.5 * (p + q);
  field.values(mid, f);
  const double ab = std::min(f[size_t(a)], f[size_t(b)]);
  double margin = INFINITY;
  for (int r = 0; r < int(f.size()); ++r)
    if (r != a && r != b) margin = std::min(margin, f[size_t(r)] - ab);
  if (margin < 0) return true;
  if (margin > length || length < 1e-3) return false;
  return third_on_segment(field, p, mid, a, b, f) || third_on_segment(field, mid, q, a, b, f);
}

bool passes_through_third(const MaterialField& field, const Dt& dt, const Facet& F) {
  const Cell n = F.cell->neighbor(F.i);
  if (F.regions[0] == 0 || dt.is_infinite(F.cell) || dt.is_infinite(n)) return false;
  const int j = n->index(F.cell);
  if (F.cell->info().clear[size_t(F.i)] && n->info().clear[size_t(j)]) return false;
  std::vector<double> f;
  if (third_on_segment(field, centre(F.cell), centre(n), F.regions[0], F.regions[1], f)) return true;
  F.cell->info().clear[size_t(F.i)] = true;
  n->info().clear[size_t(j)] = true;
  return false;
}

// The points a repair round adds: for each facet at a defective boundary edge
// (defective_facets), the labelling's crossing on its dual edge; with `resolve_gaps`, for
// each facet between two labels whose dual edge passes through a third region, the
// crossings from both ends, one on each label's side of the gap.
std::vector<Eigen::Vector3d> repair_points(const MaterialField& field, const Dt& dt, const std::vector<Facet>& facets,
                                           const std::vector<Eigen::Vector3d>& pts, bool resolve_gaps,
                                           int64_t* defects) {
  std::vector<char> kind(facets.size(), 0);  // 1: defective, 2: through a third region
  for (size_t f : defective_facets(facets, pts, field.regions(), defects)) kind[f] = 1;
  if (resolve_gaps)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, facets.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t f = r.begin(); f != r.end(); ++f)
        if (passes_through_third(field, dt, facets[f])) kind[f] = 2;
    });
  std::vector<Eigen::Vector3d> add;
  for (size_t f = 0; f < facets.size(); ++f) {
    Eigen::Vector3d x;
    if (kind[f] >= 1 && dual_crossing(field, dt, facets[f], x)) add.push_back(x);
    if (kind[f] == 2 && dual_crossing(field, dt, facets[f], x, true)) add.push_back(x);
  }
  return add;
}

// A round's repair points inserted, each but those nearer to a point inserted before it
// in the round than half their distance to every vertex that was there: several
// defective edges side by side would each get a point, a fraction of the spacing apart,
// and the slivers between them could stay (the complex's optimisation moves a vertex
// only where its smallest angle rises). A point left out comes back in the next round
// where its edge is still defective. (Waiting for every point nearer than the whole
// distance leaves a thin gap's defects to later rounds that bridge it: on the joint
// phantom a facet between the ball and the cup.)
void insert_repair_points(const std::vector<Eigen::Vector3d>& add, Dt& dt, std::vector<Eigen::Vector3d>& pts,
                          ComplexDelaunayStats& st) {
  std::vector<double> clearance(add.size());
  for (size_t k = 0; k < add.size(); ++k) {
    const Point q = dt.nearest_vertex(Point(add[k].x(), add[k].y(), add[k].z()))->point();
    clearance[k] = (Eigen::Vector3d(q.x(), q.y(), q.z()) - add[k]).norm();
  }
  std::vector<Eigen::Vector3d> inserted;
  for (size_t k = 0; k < add.size(); ++k) {
    const Eigen::Vector3d& x = add[k];
    const bool crowded = std::any_of(inserted.begin(), inserted.end(),
                                     [&](const Eigen::Vector3d& y) { return (x - y).norm() < 0.5 * clearance[k]; });
    if (crowded) continue;
    const size_t n0 = dt.number_of_vertices();
    const Dt::Vertex_handle v = dt.insert(Point(x.x(), x.y(), x.z()));
    if (dt.number_of_vertices() == n0) continue;
    v->info() = uint32_t(pts.size());
    pts.push_back(x);
    inserted.push_back(x);
    ++st.repair_points;
  }
}

}  // namespace

MaterialComplex material_delaunay(const MaterialField& field, const std::vector<ComplexParticle>& particles,
                                  ComplexDelaunayStats* stats_out, bool resolve_gaps) {
  const auto t0 = std::chrono::steady_clock::now();
  ComplexDelaunayStats st;
  st.points = int64_t(particles.size());
  if (particles.size() < 4) throw InputError("triangulate: fewer than 4 particles on the complex");
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::pair<Point, uint32_t>> in;
  for (const ComplexParticle& p : particles) {
    in.emplace_back(Point(p.p.x(), p.p.y(), p.p.z()), uint32_t(pts.size()));
    pts.push_back(p.p);
  }
  Dt dt;
  dt.insert(in.begin(), in.end());
  std::vector<Facet> facets;
  for (int round = 0;; ++round) {
    label_new_cells(field, dt);
    facets = complex_facets(dt);
    const std::vector<Eigen::Vector3d> add = repair_points(field, dt, facets, pts, resolve_gaps, &st.bad_edges);
    if (add.empty() || round == kMaxRounds) break;
    ++st.repair_rounds;
    insert_repair_points(add, dt, pts, st);
  }
  st.cells = int64_t(dt.number_of_finite_cells());
  // Triangles in a canonical order; vertices those used, in the given order.
  for (Facet& f : facets) std::rotate(f.v.begin(), std::min_element(f.v.begin(), f.v.end()), f.v.end());
  std::sort(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) {
    return a.regions != b.regions ? a.regions < b.regions : a.v < b.v;
  });
  MaterialComplex out;
  std::vector<uint32_t> index(pts.size(), UINT32_MAX);
  for (const Facet& f : facets)
    for (uint32_t v : f.v) index[v] = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (index[i] == UINT32_MAX) continue;
    index[i] = uint32_t(out.mesh.vertices.size());
    out.mesh.vertices.push_back(pts[i]);
  }
  for (const Facet& f : facets) {
    out.mesh.triangles.push_back({index[f.v[0]], index[f.v[1]], index[f.v[2]]});
    out.mesh.face_labels.push_back({int32_t(field.label(f.regions[0])), int32_t(field.label(f.regions[1]))});
  }
  st.facets = int64_t(facets.size());
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats_out) *stats_out = st;
  return out;
}

}  // namespace mpumesh::multi
