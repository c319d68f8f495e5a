#include "multi/material_delaunay.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>

#include "common/error.h"
#include "mesh/circumcentre.h"
#include "mesh/quality.h"
#include "multi/labelled_delaunay.h"
#include "multi/thin_wedges.h"

namespace mpumesh::multi {
namespace {

using namespace labelled;
// Repair rounds allowed at the start and after each refinement round.
constexpr int kMaxRounds = 100;

// The circumcentre from the vertices in id order (the same bits whichever order the cell
// lists them in).
Eigen::Vector3d centre(Cell c) {
  std::array<Dt::Vertex_handle, 4> v = {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a->info() < b->info(); });
  return robust_circumcentre(vec(v[0]->point()), vec(v[1]->point()), vec(v[2]->point()), vec(v[3]->point()));
}

// The cells not labelled yet labelled; they are returned.
std::vector<Cell> label_new_cells(const MaterialField& field, Dt& dt) {
  std::vector<Cell> todo;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
    if (c->info().region == kUnlabelled) todo.push_back(c);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, todo.size(), 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) todo[k]->info().region = field.region_at(centre(todo[k]));
  });
  return todo;
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

// The facet between cells a and b from its lower region's side, or from its finite one on
// the hull, its vertices sorted (a key: the repair needs no orientation).
Facet facet_between(const Dt& dt, Cell a, Cell b) {
  const int ra = region_of(dt, a), rb = region_of(dt, b);
  const bool from_a = dt.is_infinite(b) || (!dt.is_infinite(a) && ra < rb);
  const Cell lower = from_a ? a : b;
  const int at = from_a ? a->index(b) : b->index(a);
  Facet f{lower, at, {}, {std::min(ra, rb), std::max(ra, rb)}};
  for (int m = 0; m < 3; ++m) f.v[size_t(m)] = lower->vertex((at + 1 + m) & 3)->info();
  std::sort(f.v.begin(), f.v.end());
  return f;
}

using EdgeEnds = std::pair<Vertex, Vertex>;

// The boundary edges of a region with other than two facets, each with its widest facet,
// kept from one round to the next: an edge's regions' boundaries change only where a
// cell around it is new, so a round looks at the edges of the complex's facets on new
// cells and at those that were defective before, not at every edge.
struct DefectSearch {
  std::vector<EdgeEnds> defective;  // the edges found defective at the last look
  int64_t count = 0;                // (region, edge) pairs among them
  std::vector<Vertex> pinched;      // the vertices found pinched (pinched_at) at the last look
  int64_t pinches = 0;              // (region, vertex) pairs among them
};

// Around the edge e the regions of its cells, in turn; a region whose cells there
// make more than one run has more than two boundary facets at the edge (a union of
// cells' boundary is balanced in orientation by construction, so the count alone
// decides). Each such region's widest facet at the edge goes to `widest`; the count of
// such regions is returned.
int defects_at_edge(const Dt& dt, const EdgeRef& e, const std::vector<Eigen::Vector3d>& pts,
                    std::vector<Facet>& widest) {
  const std::vector<Cell> ring = cells_around(dt, e);
  struct Use {
    int region, facets = 0;
    double area = -1;
    Facet widest;
  };
  std::vector<Use> uses;
  for (size_t k = 0; k < ring.size(); ++k) {
    const Cell a = ring[k], b = ring[(k + 1) % ring.size()];
    const int ra = region_of(dt, a), rb = region_of(dt, b);
    if (ra == rb) continue;
    const Facet f = facet_between(dt, a, b);
    const double area = (pts[f.v[1]] - pts[f.v[0]]).cross(pts[f.v[2]] - pts[f.v[0]]).norm();
    for (const int r : {ra, rb}) {
      auto u = std::find_if(uses.begin(), uses.end(), [&](const Use& x) { return x.region == r; });
      if (u == uses.end()) u = uses.insert(uses.end(), Use{r, 0, -1, f});
      ++u->facets;
      if (area > u->area) u->area = area, u->widest = f;
    }
  }
  int n = 0;
  for (const Use& u : uses)
    if (u.facets != 2) {
      ++n;
      widest.push_back(u.widest);
    }
  return n;
}

// The edges a round looks at: those of the complex's facets on `fresh` cells and those
// defective at the last look that are still edges, each once, in the order of their
// vertex ids. (Finding an edge's cell from its vertices marks cells in the triangulation,
// so it runs on one thread.)
std::vector<EdgeRef> edges_to_check(const Dt& dt, const std::vector<Cell>& fresh, const DefectSearch& search) {
  std::vector<EdgeRef> out;
  add_edges(dt, fresh, false, out);
  for (const EdgeEnds& e : search.defective) {
    EdgeRef r{edge_key(e.first->info(), e.second->info()), Cell(), 0, 0};
    if (dt.is_edge(e.first, e.second, r.c, r.i, r.j)) out.push_back(r);
  }
  sort_unique(out);
  return out;
}

// The widest facet at each defective edge among those to check, each facet once, in the
// order of their vertex ids; `search` updated.
std::vector<Facet> defective_facets(const Dt& dt, const std::vector<Cell>& fresh, const std::vector<Eigen::Vector3d>& pts,
                                    DefectSearch& search) {
  const std::vector<EdgeRef> edges = edges_to_check(dt, fresh, search);
  std::vector<std::vector<Facet>> found(edges.size());
  std::vector<int> count(edges.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, edges.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k)
      count[k] = defects_at_edge(dt, edges[k], pts, found[k]);
  });
  search.defective.clear();
  search.count = 0;
  std::vector<Facet> out;
  for (size_t k = 0; k < edges.size(); ++k) {
    if (count[k] == 0) continue;
    const EdgeRef& e = edges[k];
    search.defective.push_back({e.c->vertex(e.i), e.c->vertex(e.j)});
    search.count += count[k];
    out.insert(out.end(), found[k].begin(), found[k].end());
  }
  std::sort(out.begin(), out.end(), [](const Facet& a, const Facet& b) { return a.v < b.v; });
  out.erase(std::unique(out.begin(), out.end(), [](const Facet& a, const Facet& b) { return a.v == b.v; }), out.end());
  return out;
}

// The widest facet of each region pinched at the vertices of the kept facets on `fresh`
// cells and at those pinched before (one thread: finding a vertex's cells marks cells);
// `search` updated.
std::vector<Facet> pinch_facets(const Dt& dt, const std::vector<Cell>& fresh, const std::vector<Eigen::Vector3d>& pts,
                                DefectSearch& search) {
  std::vector<Vertex> look = search.pinched;
  for (const Cell c : fresh)
    for (int i = 0; i < 4; ++i) {
      if (region_of(dt, c) == region_of(dt, c->neighbor(i))) continue;
      for (int m = 1; m < 4; ++m) look.push_back(c->vertex((i + m) & 3));
    }
  std::sort(look.begin(), look.end(), [](Vertex a, Vertex b) { return a->info() < b->info(); });
  look.erase(std::unique(look.begin(), look.end()), look.end());
  search.pinched.clear();
  search.pinches = 0;
  std::vector<Facet> out;
  for (const Vertex v : look) {
    const std::vector<Cell> cells = cells_at(dt, v);
    const std::vector<int> regions = pinched_at(dt, v, cells);
    if (regions.empty()) continue;
    search.pinched.push_back(v);
    search.pinches += int64_t(regions.size());
    for (const int r : regions) {
      std::optional<Facet> widest;
      double area = -1;
      for (const Cell c : cells) {
        if (region_of(dt, c) != r) continue;
        for (int k = 0; k < 4; ++k) {
          if (c->vertex(k) == v || region_of(dt, c->neighbor(k)) == r) continue;
          const Facet f = facet_between(dt, c, c->neighbor(k));
          const double a = (pts[f.v[1]] - pts[f.v[0]]).cross(pts[f.v[2]] - pts[f.v[0]]).norm();
          if (a > area) area = a, widest = f;
        }
      }
      if (widest) out.push_back(*widest);
    }
  }
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
// (`defective`), the labelling's crossing on its dual edge; with `resolve_gaps`, for each
// facet between two labels whose dual edge passes through a third region, the crossings
// from both ends, one on each label's side of the gap.
std::vector<Eigen::Vector3d> repair_points(const MaterialField& field, const Dt& dt, const std::vector<Facet>& defective,
                                           bool resolve_gaps) {
  std::vector<Eigen::Vector3d> add;
  Eigen::Vector3d x;
  for (const Facet& f : defective)
    if (dual_crossing(field, dt, f, x)) add.push_back(x);
  if (!resolve_gaps) return add;
  const std::vector<Facet> facets = complex_facets(dt);
  std::vector<char> gap(facets.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, facets.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t f = r.begin(); f != r.end(); ++f) gap[f] = passes_through_third(field, dt, facets[f]);
  });
  for (size_t f = 0; f < facets.size(); ++f) {
    if (!gap[f]) continue;
    if (dual_crossing(field, dt, facets[f], x)) add.push_back(x);
    if (dual_crossing(field, dt, facets[f], x, true)) add.push_back(x);
  }
  return add;
}

// Facets with a smaller angle than this are refined, for at most this many rounds.
constexpr double kRefineAngleDeg = 20;
constexpr int kRefineRounds = 8;

// The points a refinement round adds: for each facet with an angle below kRefineAngleDeg,
// the centre of its surface Delaunay ball (its dual edge's crossing with the labelling),
// as in Chew's surface refinement and CGAL Mesh_3's facet criteria. Such a centre lies as
// far from every vertex as the ball's radius, at least the facet's circumradius; a centre
// the projection onto the interface brought within half the facet's shortest edge of a
// vertex is left out, so no edge shorter than that is made. Where the interface
// particles are far sparser than the junction points beside them (a flat interface
// meeting a junction curve, as where a scan's cut plane crosses a bone), the facets
// between the two are needles, and the rounds grade the spacing from one to the other.
std::vector<Eigen::Vector3d> refinement_points(const MaterialField& field, const Dt& dt,
                                               const std::vector<Facet>& facets,
                                               const std::vector<Eigen::Vector3d>& pts) {
  std::vector<std::optional<Eigen::Vector3d>> at(facets.size());
  std::vector<double> shortest(facets.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, facets.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t f = r.begin(); f != r.end(); ++f) {
      const std::array<Eigen::Vector3d, 3> p = {pts[facets[f].v[0]], pts[facets[f].v[1]], pts[facets[f].v[2]]};
      if (!triangle_min_angle_below(p[0], p[1], p[2], kRefineAngleDeg)) continue;
      Eigen::Vector3d x;
      if (!dual_crossing(field, dt, facets[f], x)) continue;
      at[f] = x;
      shortest[f] = std::min({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()});
    }
  });
  // The nearest vertex on one thread: the triangulation's point location walks at random.
  std::vector<Eigen::Vector3d> add;
  for (size_t f = 0; f < facets.size(); ++f) {
    if (!at[f]) continue;
    const Eigen::Vector3d& x = *at[f];
    const Point q = dt.nearest_vertex(Point(x.x(), x.y(), x.z()))->point();
    if ((Eigen::Vector3d(q.x(), q.y(), q.z()) - x).norm() >= 0.5 * shortest[f]) add.push_back(x);
  }
  return add;
}

// A round's repair or refinement points inserted (`count` counts them), each but those
// nearer to a point inserted before it in the round than half their distance to every
// vertex that was there: several
// defective edges side by side would each get a point, a fraction of the spacing apart,
// and the slivers between them could stay (the complex's optimisation moves a vertex
// only where its smallest angle rises). A point left out comes back in the next round
// where its edge is still defective. (Waiting for every point nearer than the whole
// distance leaves a thin gap's defects to later rounds that bridge it: on the joint
// phantom a facet between the ball and the cup.)
void insert_round_points(const std::vector<Eigen::Vector3d>& add, Dt& dt, std::vector<Eigen::Vector3d>& pts,
                          int64_t& count) {
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
    ++count;
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
  DefectSearch search;
  int repair_rounds_since_refinement = 0;
  for (;;) {
    const std::vector<Cell> fresh = label_new_cells(field, dt);
    std::vector<Facet> defective = defective_facets(dt, fresh, pts, search);
    const std::vector<Facet> pinches = pinch_facets(dt, fresh, pts, search);
    defective.insert(defective.end(), pinches.begin(), pinches.end());
    st.bad_edges = search.count;
    st.pinches = search.pinches;
    if (fresh.size() == size_t(dt.number_of_finite_cells())) st.pinches_found = search.pinches;
    const std::vector<Eigen::Vector3d> repair = repair_points(field, dt, defective, resolve_gaps);
    std::vector<Eigen::Vector3d> refine;
    if (repair.empty() && st.refine_rounds < kRefineRounds)
      refine = refinement_points(field, dt, complex_facets(dt), pts);
    if (!repair.empty()) {
      if (repair_rounds_since_refinement++ == kMaxRounds) break;
      ++st.repair_rounds;
      insert_round_points(repair, dt, pts, st.repair_points);
    } else if (!refine.empty()) {
      ++st.refine_rounds;
      repair_rounds_since_refinement = 0;
      insert_round_points(refine, dt, pts, st.refine_points);
    } else {
      break;
    }
  }
  const WedgeTrimStats trim = trim_thin_wedges(dt, pts);
  st.trimmed_cells = trim.cells;
  st.trim_rounds = trim.rounds;
  st.cells = int64_t(dt.number_of_finite_cells());
  std::vector<Facet> facets = complex_facets(dt);
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
