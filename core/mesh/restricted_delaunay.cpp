#include "mesh/restricted_delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_circumcenter_traits_3.h>
#include <CGAL/Spatial_lock_grid_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <queue>
#include <unordered_map>

#include "common/error.h"
#include "common/kd_tree.h"
#include "common/lap_timer.h"
#include "compute/compute_backend.h"
#include "geometry/vertex_faces.h"
#include "mesh/cgal_geometry.h"
#include "mesh/circumcentre.h"
#include "mesh/thin_triangles.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh {
namespace {

// The circumcentre of a nearly flat tetrahedron is computed exactly and rounded
// (Robust_circumcenter_traits_3, through mesh/circumcentre.h), as CGAL's surface mesher
// does: the Voronoi vertices decide which facets are restricted.
using K = CGAL::Robust_circumcenter_traits_3<CGAL::Epick>;
struct CellData {
  double f = NAN;  // f at the circumcentre (NaN: not evaluated yet)
};
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<CellData, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
// Parallel insertion (TBB, with CGAL's spatial lock grid): the Delaunay triangulation of a
// point set is unique (CGAL's symbolic perturbation decides the degenerate cases), so the
// threads change only where the cells lie in memory, which nothing here depends on.
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Parallel_tag>;
using Lock = CGAL::Spatial_lock_grid_3<CGAL::Tag_priority_blocking>;
using Dt = CGAL::Delaunay_triangulation_3<K, Tds, CGAL::Default, Lock>;
using Point = K::Point_3;
using Cell = Dt::Cell_handle;

Eigen::Vector3d vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// A cell's circumcentre from its vertices in id order: the same bits whichever order the
// cell lists them in (which depends on the insertion history and, inserted in parallel, on
// the threads), so that f's sign there, hence the mesh, is the same every run.
bool by_id(const Dt::Vertex_handle& a, const Dt::Vertex_handle& b) { return a->info() < b->info(); }

Eigen::Vector3d circumcentre(const Dt& dt, Cell c) {
  std::array<Dt::Vertex_handle, 4> v = {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
  std::sort(v.begin(), v.end(), by_id);
  return robust_circumcentre(vec(v[0]->point()), vec(v[1]->point()), vec(v[2]->point()), vec(v[3]->point()));
}

bool inside(const Dt& dt, Cell c) { return !dt.is_infinite(c) && c->info().f < 0; }

// A restricted facet: the facet of `cell` opposite vertex `i`, with `cell` inside and its
// neighbour outside; v holds its vertex ids ordered so the normal points out.
struct RFacet {
  Cell cell;
  int i;
  std::array<uint32_t, 3> v;
};

// f, but positive outside the fitted points' bounding box (widened by 0.5% of the cube):
// no surface lies there, while the leaves' polynomials, extrapolated into the cube's
// margin, can go negative (on the sample CT, f = -35 to -650 mm 4 to 16 mm beyond the
// points at the volume's border), and a Voronoi vertex there would put facets on a sheet
// that is not there.
bool within_data(const mpu::MpuSurface& s, const Eigen::Vector3d& x) {
  const double margin = 0.005 * s.box_size;
  return !((x.array() < s.data_min.array() - margin).any() || (x.array() > s.data_max.array() + margin).any());
}
double f_within_data(const mpu::MpuSurface& s, const Eigen::Vector3d& x) {
  return within_data(s, x) ? mpu::evaluate_f(s, x) : s.box_size;
}

// The Voronoi edge dual to facet (c, i) runs from c's circumcentre to its neighbour's (or,
// for a facet of the convex hull, out along the facet's outward normal). Its crossing of
// f = 0, by bisection to within 5 µm, from the inside end a (f < 0) to b (f >= 0).
Eigen::Vector3d crossing(const mpu::MpuSurface& s, const Dt& dt, Cell c, int i) {
  const Eigen::Vector3d a = circumcentre(dt, c);
  const Cell n = c->neighbor(i);
  Eigen::Vector3d b;
  if (dt.is_infinite(n)) {
    // The facet's vertices in id order (see circumcentre).
    std::array<Dt::Vertex_handle, 3> f = {c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
    std::sort(f.begin(), f.end(), by_id);
    const Eigen::Vector3d p0 = vec(f[0]->point()), p1 = vec(f[1]->point()), p2 = vec(f[2]->point()),
                          pi = vec(c->vertex(i)->point());
    Eigen::Vector3d dir = (p1 - p0).cross(p2 - p0);
    if (dir.dot(pi - p0) > 0) dir = -dir;
    b = a + dir.normalized() * (s.box_size * 2 + (a - 0.5 * (s.data_min + s.data_max)).norm());
  } else {
    b = circumcentre(dt, n);
  }
  Eigen::Vector3d lo = a, hi = b;
  for (int k = 0; k < 60 && (hi - lo).squaredNorm() > 25e-6; ++k) {
    const Eigen::Vector3d m = 0.5 * (lo + hi);
    (f_within_data(s, m) < 0 ? lo : hi) = m;
  }
  return 0.5 * (lo + hi);
}

// f at the circumcentre of every finite cell not evaluated yet (new cells): the centres in
// parallel, f on the backend (the CPU reference when null; a GPU computes it in float32,
// which moves only which side of f = 0 a Voronoi vertex within ~1e-4 mm of it falls on:
// each cell still gets one sign, so the facets still bound a union of cells). Marks the
// vertices of those cells in `touched` (by id). The new cells are looked for among all
// when `inserted` is null, else among the cells around the vertices inserted since the
// last call: a Delaunay insertion joins the new vertex to the boundary of the cells it
// removes, so every cell it makes has that vertex. (Rather than all of the sample CT's
// 300,000 cells scanned in each of its 20 repair rounds; the mesh is the same.)
void evaluate_new_cells(const mpu::MpuSurface& s, Dt& dt, std::vector<char>& touched, ComputeBackend* backend,
                        const std::vector<Dt::Vertex_handle>* inserted) {
  std::vector<Cell> todo;
  if (inserted) {
    std::vector<Cell> around;
    for (const Dt::Vertex_handle& v : *inserted) dt.finite_incident_cells(v, std::back_inserter(around));
    tbb::parallel_sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    for (Cell c : around)
      if (std::isnan(c->info().f)) todo.push_back(c);
  } else {
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
      if (std::isnan(c->info().f)) todo.push_back(c);
  }
  for (Cell c : todo)
    for (int k = 0; k < 4; ++k) touched[c->vertex(k)->info()] = 1;
  std::vector<Eigen::Vector3d> centres(todo.size());
  std::vector<double> f(todo.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, todo.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      centres[k] = circumcentre(dt, todo[k]);
      if (!backend) f[k] = f_within_data(s, centres[k]);
    }
  });
  if (backend) {
    // Only the centres within the data's box go to the device (see f_within_data).
    std::vector<Eigen::Vector3d> within;
    std::vector<size_t> at;
    for (size_t k = 0; k < todo.size(); ++k) {
      if (within_data(s, centres[k])) {
        at.push_back(k);
        within.push_back(centres[k]);
      } else {
        f[k] = s.box_size;
      }
    }
    const std::vector<double> fw = backend->mpu_f(s, within);
    for (size_t j = 0; j < at.size(); ++j) f[at[j]] = fw[j];
  }
  for (size_t k = 0; k < todo.size(); ++k) {
    if (!std::isfinite(f[k]))
      throw NumericalError("triangulate: the surface is not finite (f = " + std::to_string(f[k]) + ") at (" +
                           std::to_string(centres[k].x()) + ", " + std::to_string(centres[k].y()) + ", " +
                           std::to_string(centres[k].z()) + ")");
    todo[k]->info().f = f[k];
  }
}

// The restricted facets: between an inside cell (f < 0 at its circumcentre) and an outside
// one (f >= 0, or infinite). They bound a union of tetrahedra, so every edge has an even
// number of them and the normals (inside to outside) agree along every edge.
void add_restricted_facets(const Dt& dt, Cell c, std::vector<RFacet>& out) {
  if (!inside(dt, c)) return;
  const auto orientation = dt.geom_traits().orientation_3_object();
  for (int i = 0; i < 4; ++i) {
    if (inside(dt, c->neighbor(i))) continue;
    auto a = c->vertex((i + 1) & 3), b = c->vertex((i + 2) & 3), d = c->vertex((i + 3) & 3);
    if (orientation(a->point(), b->point(), d->point(), c->vertex(i)->point()) == CGAL::POSITIVE) std::swap(b, d);
    out.push_back({c, i, {a->info(), b->info(), d->info()}});
  }
}

// In the cells' order; their orientation tests in parallel, chunk by chunk (on one core
// the sample CT's 300,000 cells take 0.03 s a call).
std::vector<RFacet> restricted_facets(const Dt& dt) {
  std::vector<Cell> cells;
  cells.reserve(dt.number_of_finite_cells());
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) cells.push_back(c);
  constexpr size_t kChunk = 8192;
  std::vector<std::vector<RFacet>> parts((cells.size() + kChunk - 1) / kChunk);
  tbb::parallel_for(size_t(0), parts.size(), [&](size_t k) {
    for (size_t i = k * kChunk; i < std::min(cells.size(), (k + 1) * kChunk); ++i)
      add_restricted_facets(dt, cells[i], parts[k]);
  });
  std::vector<RFacet> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// The restricted facets of the cells around the vertices marked in `touched`, each once.
std::vector<RFacet> restricted_facets_near(const Dt& dt, const std::vector<char>& touched) {
  std::vector<Cell> cells;
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v)
    if (touched[v->info()]) dt.finite_incident_cells(v, std::back_inserter(cells));
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<RFacet> out;
  for (Cell c : cells) add_restricted_facets(dt, c, out);
  return out;
}

// The facets around each non-manifold edge (more than two facets) and around each
// non-manifold vertex (its facets form more than one fan), one group per element; only
// elements at a vertex marked in `check` (which must list every facet at those vertices).
std::vector<std::vector<uint32_t>> non_manifold_groups(const std::vector<RFacet>& facets,
                                                       const std::vector<char>& check) {
  std::vector<std::vector<uint32_t>> groups;
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  edges.reserve(3 * facets.size());
  for (uint32_t f = 0; f < facets.size(); ++f)
    for (int e = 0; e < 3; ++e) edges.emplace_back(edge_key(facets[f].v[size_t(e)], facets[f].v[size_t((e + 1) % 3)]), f);
  tbb::parallel_sort(edges.begin(), edges.end());  // (edge, facet) pairs are distinct: one order
  for (size_t a = 0, b; a < edges.size(); a = b) {
    for (b = a + 1; b < edges.size() && edges[b].first == edges[a].first;) ++b;
    const uint64_t key = edges[a].first;
    if (b - a > 2 && (check[uint32_t(key >> 32)] || check[uint32_t(key)])) {
      groups.emplace_back();
      for (size_t k = a; k < b; ++k) groups.back().push_back(edges[k].second);
    }
  }
  // Fans: facets of a vertex joined through the edges they share.
  std::vector<std::pair<uint32_t, uint32_t>> star;  // (vertex, facet)
  star.reserve(3 * facets.size());
  for (uint32_t f = 0; f < facets.size(); ++f)
    for (uint32_t v : facets[f].v) star.emplace_back(v, f);
  tbb::parallel_sort(star.begin(), star.end());
  std::vector<std::pair<uint32_t, uint32_t>> spokes;  // (other vertex, local facet)
  std::vector<uint32_t> parent;
  for (size_t a = 0, b; a < star.size(); a = b) {
    for (b = a + 1; b < star.size() && star[b].first == star[a].first;) ++b;
    const uint32_t v = star[a].first, n = uint32_t(b - a);
    if (!check[v]) continue;
    spokes.clear();
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
    for (uint32_t k = 0; k < n; ++k)
      for (uint32_t w : facets[star[a + k].second].v)
        if (w != v) spokes.emplace_back(w, k);
    std::sort(spokes.begin(), spokes.end());
    auto root = [&](uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    uint32_t fans = n;
    for (size_t k = 1; k < spokes.size(); ++k)
      if (spokes[k].first == spokes[k - 1].first) {
        const uint32_t x = root(spokes[k].second), y = root(spokes[k - 1].second);
        if (x != y) parent[x] = y, --fans;
      }
    if (fans > 1) {
      groups.emplace_back();
      for (size_t k = a; k < b; ++k) groups.back().push_back(star[k].second);
    }
  }
  return groups;
}

// A restricted facet much wider than the sampling around it: its dual Voronoi edge crosses
// a sheet of f that no point samples (the small unsampled ball between two sampled spheres
// of RestrictedDelaunay.SamplesASheetBetweenSampledOnes: a tube of facets 20 mm long
// joined them, closed and manifold, so the manifold repair saw nothing). Such a facet gets
// the crossing as a point, as CGAL's surface mesher refines facets over its size bound:
// the sheet is then sampled and meshed on its own (and removed when no particle holds it,
// see sampled_components). The candidates here: facets with a vertex in `check` whose
// circumradius exceeds kOversize times the longest of their vertices' shortest restricted
// edges; each with that bound, which its surface Delaunay ball (no smaller than the
// circumradius) must exceed too. (On the sample CT 56-474 facets pass, at 20,000-40,000
// particles, where the manifold repair adds 15,000-2,000 points; the quality figures stay.)
constexpr double kOversize = 3;
std::vector<std::pair<uint32_t, double>> oversized_facets(const std::vector<RFacet>& facets, const std::vector<char>& check,
                                                          size_t ids) {
  auto corners = [](const RFacet& f) {
    return std::array<Dt::Vertex_handle, 3>{f.cell->vertex((f.i + 1) & 3), f.cell->vertex((f.i + 2) & 3),
                                            f.cell->vertex((f.i + 3) & 3)};
  };
  std::vector<double> shortest(ids, INFINITY);
  for (const RFacet& f : facets) {
    const auto h = corners(f);
    for (int e = 0; e < 3; ++e) {
      const Dt::Vertex_handle a = h[size_t(e)], b = h[size_t((e + 1) % 3)];
      const double len = (vec(a->point()) - vec(b->point())).norm();
      shortest[a->info()] = std::min(shortest[a->info()], len);
      shortest[b->info()] = std::min(shortest[b->info()], len);
    }
  }
  std::vector<std::pair<uint32_t, double>> out;
  for (uint32_t k = 0; k < facets.size(); ++k) {
    const auto h = corners(facets[k]);
    if (!check[h[0]->info()] && !check[h[1]->info()] && !check[h[2]->info()]) continue;
    const Eigen::Vector3d p0 = vec(h[0]->point()), p1 = vec(h[1]->point()), p2 = vec(h[2]->point());
    const double a = (p1 - p2).norm(), b = (p0 - p2).norm(), c = (p0 - p1).norm();
    const double twice_area = (p1 - p0).cross(p2 - p0).norm();
    const double bound = kOversize * std::max({shortest[h[0]->info()], shortest[h[1]->info()], shortest[h[2]->info()]});
    // circumradius a b c / (4 area) > bound, without dividing by a vanishing area
    if (a * b * c > 2 * bound * twice_area) out.emplace_back(k, bound);
  }
  return out;
}

// Where a thin plate passes through a particle's Voronoi cell with both of its sides, every
// Voronoi edge there crosses f = 0 twice or not at all, and the particle gets no restricted
// facet: the plate drops out of the mesh (on the sample CT, a bone fragment of 272
// marching-cubes triangles by the zygomatic arch, at some particle counts). The other side
// of the plate, found along ∓∇f from the particle within `reach` (8 even steps, then 30
// bisections), is the point the sample lacks there; nullopt when no other sheet is that
// near within the data's box.
std::optional<Eigen::Vector3d> opposite_sheet(const mpu::MpuSurface& s, const Eigen::Vector3d& p, double reach) {
  const mpu::Sample e = mpu::evaluate_fg(s, p);
  const Eigen::Vector3d& g = e.g;
  if (!(g.norm() > 0) || !(reach > 0)) return std::nullopt;
  // p must lie on f = 0 (|f| / |∇f| within 5% of the reach), and the search starts past
  // its own sheet (twice that distance, at least 0.1% of the reach): a particle left where
  // ∇f nearly vanishes (between two sheets) lies on no sheet, and from it the bisection
  // went to p itself. On the sample CT fitted with ε0 = 0.2 mm, 81 such points were put
  // 1e-13 to 1e-10 mm from their particles (|f| / |∇f| there up to 2 mm), and one of them
  // made two 0° triangles.
  const double off = std::abs(e.f) / g.norm();
  if (!(off < 0.05 * reach)) return std::nullopt;
  const double a0 = std::max(1e-3 * reach, 2 * off);
  const Eigen::Vector3d n = g.normalized();
  std::optional<Eigen::Vector3d> best;
  double best_t = INFINITY;
  constexpr int kSteps = 8;
  for (const double dir : {-1.0, 1.0}) {
    // Inward (dir < 0) f is negative until the other sheet; outward positive until the next.
    // The data's box is no sheet: the search stops at it (f_within_data's jump there would
    // put points on the box, beside the skull where the volume cuts it).
    auto crossed = [&](double t) { return dir * mpu::evaluate_f(s, p + dir * t * n) < 0; };
    if (crossed(a0)) continue;  // a sheet within a0 of p: none that the mesh could hold
    for (int k = 1; k <= kSteps; ++k) {
      const double t = reach * k / kSteps;
      if (t >= best_t || !within_data(s, p + dir * t * n)) break;
      if (!crossed(t)) continue;
      double a = std::max(a0, reach * (k - 1) / kSteps), b = t;
      for (int it = 0; it < 30; ++it) {
        const double m = 0.5 * (a + b);
        (crossed(m) ? b : a) = m;
      }
      best_t = 0.5 * (a + b);
      best = p + dir * best_t * n;
      break;
    }
  }
  return best;
}

// The points that lost sheets need (opposite_sheet), from the restricted facets of the
// triangulation so far: for each particle on no facet that lies farther than half its
// nearest neighbour's distance (its reach) from the facets around its Delaunay neighbours
// (beside the mesh, not one more sample of it), the other side of its plate within that
// reach; in particle order, each only where neither a Delaunay neighbour of its particle
// nor a point taken before lies within half the reach (the sheet points of neighbouring
// lost particles land close together, and two of them 0.25 mm apart made a needle of 10°
// on the sample CT that the cleanup could not mend). None within a reach of the data's
// box, where the volume cuts the anatomy: the surface there folds round the cut face, no
// plate, and its sheet points made the sample CT's smallest angles (10-14°, at y = -0.4 mm).
std::vector<Eigen::Vector3d> lost_sheet_points(const mpu::MpuSurface& s, const Dt& dt, const std::vector<RFacet>& facets,
                                               const std::vector<Eigen::Vector3d>& points,
                                               const std::vector<Eigen::Vector3d>& repair) {
  const VertexFaces vf = vertex_faces(points.size() + repair.size(), facets.size(),
                                      [&](size_t f) -> const std::array<uint32_t, 3>& { return facets[f].v; });
  const std::vector<uint32_t>& first = vf.first;
  auto point = [&](uint32_t id) {
    const Eigen::Vector3d& x = id < points.size() ? points[id] : repair[id - points.size()];
    return Point(x.x(), x.y(), x.z());
  };
  struct Lost {
    uint32_t id;
    Eigen::Vector3d x;
    double reach;
    std::vector<Eigen::Vector3d> neighbours;
  };
  std::vector<Lost> lost;
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    if (v->info() >= points.size() || first[v->info()] != first[v->info() + 1]) continue;
    std::vector<Dt::Vertex_handle> adjacent;
    dt.finite_adjacent_vertices(v, std::back_inserter(adjacent));
    double nearest = INFINITY, to_mesh = INFINITY;
    for (const auto& w : adjacent) {
      nearest = std::min(nearest, (vec(w->point()) - vec(v->point())).norm());
      for (uint32_t k = first[w->info()]; k < first[w->info() + 1]; ++k) {
        const auto& t = facets[vf.faces[k]].v;
        to_mesh = std::min(to_mesh, CGAL::squared_distance(v->point(), K::Triangle_3(point(t[0]), point(t[1]), point(t[2]))));
      }
    }
    to_mesh = std::sqrt(to_mesh);
    const Eigen::Vector3d x = vec(v->point());
    const double border = std::min((x - s.data_min).minCoeff(), (s.data_max - x).minCoeff());
    if (!(to_mesh > 0.5 * nearest) || border < nearest) continue;
    Lost l{v->info(), x, nearest, {}};
    for (const auto& w : adjacent) l.neighbours.push_back(vec(w->point()));
    lost.push_back(std::move(l));
  }
  // In particle order (the vertices' order in memory depends on the parallel insertion).
  std::sort(lost.begin(), lost.end(), [](const Lost& a, const Lost& b) { return a.id < b.id; });
  std::vector<std::optional<Eigen::Vector3d>> other(lost.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, lost.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) other[k] = opposite_sheet(s, lost[k].x, lost[k].reach);
  });
  std::vector<Eigen::Vector3d> out;
  for (size_t k = 0; k < lost.size(); ++k) {
    if (!other[k]) continue;
    const double gap2 = 0.25 * lost[k].reach * lost[k].reach;
    auto close = [&](const Eigen::Vector3d& q) { return (q - *other[k]).squaredNorm() < gap2; };
    const Dt::Vertex_handle nv = dt.nearest_vertex(Point(other[k]->x(), other[k]->y(), other[k]->z()));
    if ((nv->info() != lost[k].id && close(vec(nv->point()))) ||
        std::any_of(lost[k].neighbours.begin(), lost[k].neighbours.end(), close) ||
        std::any_of(out.begin(), out.end(), close))
      continue;
    out.push_back(*other[k]);
  }
  return out;
}

}  // namespace

int64_t orient_components(TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& outward) {
  auto& tris = mesh.triangles;
  // The faces of each vertex (compressed rows; an edge map of vectors took 0.1 s on the
  // sample CT). The faces of edge ab are those of a that hold b.
  const VertexFaces star =
      vertex_faces(mesh.vertices.size(), tris.size(), [&](size_t f) -> const std::array<uint32_t, 3>& { return tris[f]; });
  const std::vector<uint32_t>& first = star.first;
  const std::vector<uint32_t>& vf = star.faces;
  auto holds = [&](uint32_t g, uint32_t v) { return tris[g][0] == v || tris[g][1] == v || tris[g][2] == v; };
  // Does triangle t traverse the edge a -> b?
  auto forward = [&](uint32_t t, uint32_t a, uint32_t b) {
    for (int e = 0; e < 3; ++e)
      if (tris[t][size_t(e)] == a && tris[t][size_t((e + 1) % 3)] == b) return true;
    return false;
  };
  std::vector<int32_t> comp(tris.size(), -1);
  int64_t flipped = 0;
  for (uint32_t start = 0; start < tris.size(); ++start) {
    if (comp[start] >= 0) continue;
    const int32_t c = int32_t(start);
    std::vector<uint32_t> members{start};
    std::queue<uint32_t> q;
    q.push(start);
    comp[start] = c;
    while (!q.empty()) {
      const uint32_t f = q.front();
      q.pop();
      for (int e = 0; e < 3; ++e) {
        const uint32_t a = tris[f][size_t(e)], b = tris[f][size_t((e + 1) % 3)];
        for (uint32_t k = first[a]; k < first[a + 1]; ++k) {
          const uint32_t g = vf[k];
          if (g == f || comp[g] >= 0 || !holds(g, b)) continue;
          if (forward(g, a, b)) std::swap(tris[g][1], tris[g][2]);  // must run b -> a
          comp[g] = c;
          members.push_back(g);
          q.push(g);
        }
      }
    }
    double vote = 0;
    for (uint32_t f : members) {
      const auto& t = tris[f];
      const Eigen::Vector3d& p0 = mesh.vertices[t[0]];
      const Eigen::Vector3d n = (mesh.vertices[t[1]] - p0).cross(mesh.vertices[t[2]] - p0);
      vote += n.dot(outward[t[0]] + outward[t[1]] + outward[t[2]]);
    }
    if (vote < 0) {
      for (uint32_t f : members) std::swap(tris[f][1], tris[f][2]);
      ++flipped;
    }
  }
  return flipped;
}

namespace {

// One triangulation's state: the Delaunay triangulation of the particles and the repair
// points, the restricted facets, and the figures.
class Triangulation {
 public:
  Triangulation(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points, int64_t max_repair_points,
                ComputeBackend* backend, RestrictedDelaunayStats& stats)
      : s(s),
        points(points),
        backend(backend),
        stats(stats),
        lock(bounding_box(points), 50),
        dt(K(), &lock),
        max_repair(max_repair_points > 0 ? size_t(max_repair_points) : std::max<size_t>(20000, points.size())),
        touched(points.size()) {}
  // The Delaunay triangulation of the particles (in parallel, repeatably).
  void delaunay();
  // The manifold repair and the lost sheets: after it, `facets` are the restricted facets.
  void make_manifold(LapTimer& timer);
  // Components that no particle holds, or mostly off the sample (see sampled_components).
  void remove_spurious();
  // The facets as an oriented mesh: canonical order, used points then repair points.
  TriangleMesh to_mesh();

 private:
  static CGAL::Bbox_3 bounding_box(const std::vector<Eigen::Vector3d>& points) {
    Eigen::Vector3d lo = points[0], hi = lo;
    for (const auto& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    return CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
  }
  // Inserts points as repair points (in an order that does not depend on where the cells
  // lie in memory); the new vertices go to `inserted`. Each point comes with the radius of
  // its facet's ball (0: none): a point closer than kRepairMerge of that radius to one
  // inserted before it in the same call is left out, both crossings standing for one
  // missing point. (Two groups' largest facets can have Voronoi edges that cross f = 0 at
  // nearly one place; on the sample CT fitted with ε0 = 0.347 mm two repair points 3 µm
  // apart made triangles of 0.2° and 0.4° that neither collapse nor relaxation could mend.
  // A point left out is found again in the next round if it is still needed.)
  static constexpr double kRepairMerge = 0.05;
  void insert_repair(std::vector<std::pair<Eigen::Vector3d, double>> add, Cell hint);
  // One round of the manifold repair; true when nothing is left to repair.
  bool repair_round(int round, LapTimer& timer);
  // Points on sheets no facet reaches (lost_sheet_points); false when there are none.
  bool add_sheet_points();

  const mpu::MpuSurface& s;
  const std::vector<Eigen::Vector3d>& points;
  ComputeBackend* backend;
  RestrictedDelaunayStats& stats;
  Lock lock;
  Dt dt;
  size_t max_repair;
  // After the first round only the cells the new points made are looked at again.
  std::vector<Eigen::Vector3d> repair;  // id - points.size() -> position
  std::vector<RFacet> facets;
  std::vector<char> touched;
  std::vector<Dt::Vertex_handle> inserted;  // the last round's repair points
  std::vector<char> is_sheet;               // per repair point: a lost-sheet point
};

void Triangulation::delaunay() {
    // Of points at one position only the first is inserted: which of them the triangulation
    // would keep depends, inserted in parallel, on the threads.
    std::vector<uint32_t> order(points.size());
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&](uint32_t a, uint32_t b) {
      return std::lexicographical_compare(points[a].data(), points[a].data() + 3, points[b].data(),
                                          points[b].data() + 3) ||
             (points[a] == points[b] && a < b);
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::pair<Point, uint32_t>> pts;
    pts.reserve(points.size());
    for (size_t k = 0; k < order.size(); ++k) {
      const uint32_t i = order[k];
      if (k > 0 && points[i] == points[order[k - 1]]) continue;
      pts.emplace_back(Point(points[i].x(), points[i].y(), points[i].z()), i);
    }
    dt.insert(pts.begin(), pts.end());
}

void Triangulation::insert_repair(std::vector<std::pair<Eigen::Vector3d, double>> add, Cell hint) {
  std::sort(add.begin(), add.end(), [](const auto& a, const auto& b) {
    return std::lexicographical_compare(a.first.data(), a.first.data() + 3, b.first.data(), b.first.data() + 3);
  });
  inserted.clear();
  // The points placed so far come in the order of their x (the sort above), so only
  // those within the merge distance in x, the last few, can be that near.
  std::vector<Eigen::Vector3d> placed;
  for (const auto& [x, radius] : add) {
    bool near = false;
    const double bound = kRepairMerge * radius;
    for (size_t k = placed.size(); k-- > 0 && !near && x.x() - placed[k].x() < bound;)
      near = (x - placed[k]).norm() < bound;
    if (near) {
      ++stats.repair_merged;
      continue;
    }
    placed.push_back(x);
    const size_t n0 = dt.number_of_vertices();
    const Dt::Vertex_handle v = dt.insert(Point(x.x(), x.y(), x.z()), hint);
    if (dt.number_of_vertices() > n0) {
      v->info() = uint32_t(points.size() + repair.size());
      repair.push_back(x);
      inserted.push_back(v);
    }
    hint = v->cell();
  }
}

bool Triangulation::repair_round(int round, LapTimer& timer) {
  touched.assign(points.size() + repair.size(), 0);
  stats.seconds_repair += timer.lap();
  evaluate_new_cells(s, dt, touched, backend, round == 0 ? nullptr : &inserted);
  stats.seconds_evaluate += timer.lap();
  facets = round == 0 ? restricted_facets(dt) : restricted_facets_near(dt, touched);
  const std::vector<std::vector<uint32_t>> groups = non_manifold_groups(facets, touched);
  const std::vector<std::pair<uint32_t, double>> wide = oversized_facets(facets, touched, touched.size());
  if (groups.empty() && wide.empty()) return true;
  if (repair.size() >= max_repair || round >= 100)
    throw NumericalError("triangulate: " + std::to_string(groups.size()) +
                         " non-manifold edges or vertices and " + std::to_string(wide.size()) +
                         " wide facets remain after " + std::to_string(repair.size()) +
                         " repair points in " + std::to_string(round) +
                         " rounds: the particles are too sparse for this surface (ask for more)");
  // The largest facet of each group, each crossing computed once and each facet once.
  // The crossings (bisection on f) are found in parallel.
  std::vector<uint32_t> need;
  for (const auto& g : groups) need.insert(need.end(), g.begin(), g.end());
  for (const auto& w : wide) need.push_back(w.first);
  std::sort(need.begin(), need.end());
  need.erase(std::unique(need.begin(), need.end()), need.end());
  std::vector<std::pair<Eigen::Vector3d, double>> found(need.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, need.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const RFacet& rf = facets[need[k]];
      const Eigen::Vector3d x = crossing(s, dt, rf.cell, rf.i);
      // The ball's radius: the distance to the facet's vertex of smallest id.
      const Dt::Vertex_handle first = std::min(
          {rf.cell->vertex((rf.i + 1) & 3), rf.cell->vertex((rf.i + 2) & 3), rf.cell->vertex((rf.i + 3) & 3)}, by_id);
      found[k] = {x, (x - vec(first->point())).norm()};
    }
  });
  std::unordered_map<uint32_t, std::pair<Eigen::Vector3d, double>> ball;  // facet -> (crossing, radius)
  for (size_t k = 0; k < need.size(); ++k) ball.emplace(need[k], found[k]);
  // Equal radii (cospherical points give several facets one Voronoi vertex) go to the
  // facet with the smallest vertex ids, not to the first in memory: the parallel
  // insertion puts cells in a different order each run.
  auto sorted_ids = [&](uint32_t f) {
    std::array<uint32_t, 3> v = facets[f].v;
    std::sort(v.begin(), v.end());
    return v;
  };
  std::vector<uint32_t> chosen;
  for (const auto& g : groups) {
    uint32_t best = g[0];
    double best_r = -1;
    for (uint32_t f : g) {
      const double r = ball.at(f).second;
      if (r > best_r || (r == best_r && sorted_ids(f) < sorted_ids(best))) best_r = r, best = f;
    }
    chosen.push_back(best);
  }
  for (const auto& [f, bound] : wide)
    if (ball.at(f).second > bound) {
      chosen.push_back(f);
      ++stats.wide_facets;
    }
  if (chosen.empty()) return true;  // no group, and no wide facet's ball past its bound
  stats.repair_rounds = round + 1;
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  std::vector<std::pair<Eigen::Vector3d, double>> add;
  for (uint32_t f : chosen) add.push_back(ball.at(f));
  const size_t before = repair.size();
  insert_repair(std::move(add), facets[chosen[0]].cell);
  is_sheet.resize(repair.size(), 0);
  if (repair.size() == before)
    throw NumericalError("triangulate: the manifold repair made no progress (" + std::to_string(groups.size()) +
                         " non-manifold edges or vertices)");
  return false;
}

bool Triangulation::add_sheet_points() {
  const size_t before = repair.size();
  const std::vector<Eigen::Vector3d> sheet = lost_sheet_points(s, dt, facets, points, repair);
  if (!sheet.empty()) {
    std::vector<std::pair<Eigen::Vector3d, double>> add;
    for (const Eigen::Vector3d& x : sheet) add.push_back({x, 0.0});
    insert_repair(add, dt.infinite_cell());
  }
  stats.sheet_points += int64_t(repair.size() - before);
  is_sheet.resize(repair.size(), 1);
  return repair.size() != before;
}

// Manifold repair, as CGAL's surface mesher does with its Manifold_tag, but bounded and
// repeatable: while some edge has more than two restricted facets or some vertex more
// than one fan, each such element gets a point where the Voronoi edge of its largest
// facet (the one whose surface Delaunay ball, centred on that crossing, is widest)
// crosses f = 0; the cells that the new points replace are evaluated, and the facets
// found again.
void Triangulation::make_manifold(LapTimer& timer) {
  int round = 0;
  for (int pass = 0;; ++pass) {  // the manifold repair, then lost sheets (below)
    while (!repair_round(round, timer)) ++round;
    // Lost sheets, twice at most, each time followed by the manifold repair around the
    // new points.
    facets = restricted_facets(dt);
    if (pass == 2 || !add_sheet_points()) break;
    ++round;
  }
}

void Triangulation::remove_spurious() {
    std::vector<std::array<uint32_t, 3>> tris(facets.size());
    for (size_t f = 0; f < facets.size(); ++f) tris[f] = facets[f].v;
    // Off the sample: a repair point farther than kOffSample particle spacings from every
    // particle (the particle system's reach off the data is 4 pool radii, data_support.h).
    constexpr double kOffSample = 4;
    std::vector<char> off(repair.size(), 0);
    if (!repair.empty()) {
      const PointIndex index(points);
      const KdTree& tree = index.tree;
      const double reach = kOffSample * median_spacing(points, tree, 1);
      tbb::parallel_for(tbb::blocked_range<size_t>(0, repair.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t k = r.begin(); k != r.end(); ++k) {
          uint32_t idx;
          double d2;
          nanoflann::KNNResultSet<double, uint32_t> rs(1);
          rs.init(&idx, &d2);
          tree.findNeighbors(rs, repair[k].data(), nanoflann::SearchParams());
          off[k] = !is_sheet[k] && d2 > reach * reach;
        }
      });
    }
    const std::vector<char> keep = sampled_components(
        tris, points.size() + repair.size(),
        [&](uint32_t id) { return id < points.size() || is_sheet[id - points.size()]; }, &stats.spurious_components,
        [&](uint32_t id) { return id >= points.size() && off[id - points.size()]; });
    size_t n = 0;
    for (size_t f = 0; f < facets.size(); ++f)
      if (keep[f]) facets[n++] = facets[f];
    stats.spurious_triangles = int64_t(facets.size() - n);
    facets.resize(n);
}

TriangleMesh Triangulation::to_mesh() {
  // Triangles in a canonical order (each rotated to start at its smallest id, then sorted),
  // not in the order the cells lie in memory, which depends on the insertion history.
  for (RFacet& f : facets) std::rotate(f.v.begin(), std::min_element(f.v.begin(), f.v.end()), f.v.end());
  std::sort(facets.begin(), facets.end(), [](const RFacet& a, const RFacet& b) { return a.v < b.v; });
  // Vertices: the given points that the facets use, in their order, then the repair points.
  const size_t ids = points.size() + repair.size();
  std::vector<uint32_t> index(ids, UINT32_MAX);
  for (const RFacet& f : facets)
    for (uint32_t v : f.v) index[v] = 0;
  TriangleMesh mesh;
  for (size_t id = 0; id < ids; ++id) {
    if (index[id] == UINT32_MAX) continue;
    index[id] = uint32_t(mesh.vertices.size());
    mesh.vertices.push_back(id < points.size() ? points[id] : repair[id - points.size()]);
    if (id >= points.size()) ++stats.repair_points;
  }
  stats.unused_points = int64_t(points.size()) - (int64_t(mesh.vertices.size()) - stats.repair_points);
  mesh.triangles.reserve(facets.size());
  for (const RFacet& f : facets) mesh.triangles.push_back({index[f.v[0]], index[f.v[1]], index[f.v[2]]});
  std::vector<Eigen::Vector3d> outward(mesh.vertices.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.vertices.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) outward[i] = mpu::evaluate_fg(s, mesh.vertices[i]).g;
  });
  stats.flipped_components = orient_components(mesh, outward);
  return mesh;
}

// The repair points leave a few thin triangles (mesh/thin_triangles.h). The restricted
// Delaunay facets are faces of one tetrahedralization, so no two of them intersect; a
// collapse, flip or relaxed vertex can make a triangle that cuts another (across a thin
// plate). Such changes are found (the changed triangles against all, exact predicates)
// and the cleanup is done again with their vertices frozen; after three tries, none is
// kept.
void clean_up(const mpu::MpuSurface& s, TriangleMesh& mesh, RestrictedDelaunayStats& stats) {
  const TriangleMesh raw = mesh;
  std::vector<std::array<uint32_t, 3>> raw_tris;
  for (auto t : raw.triangles) {
    std::sort(t.begin(), t.end());
    raw_tris.push_back(t);
  }
  std::sort(raw_tris.begin(), raw_tris.end());
  std::vector<char> frozen(raw.vertices.size(), 0);
  const auto surface_distance = [&s](const Eigen::Vector3d& x) {
    const mpu::Sample e = mpu::evaluate_fg(s, x);
    const double g = e.g.norm();
    return g > 0 ? std::abs(e.f) / g : INFINITY;
  };
  // A point moved back onto f = 0 by four Newton steps.
  const auto onto_surface = [&s](Eigen::Vector3d x) {
    for (int k = 0; k < 4; ++k) {
      const mpu::Sample e = mpu::evaluate_fg(s, x);
      const double g2 = e.g.squaredNorm();
      if (!(g2 > 0) || e.leaves == 0) return Eigen::Vector3d(Eigen::Vector3d::Constant(NAN));
      x -= e.f / g2 * e.g;
    }
    return x;
  };
  ThinTriangleStats tt;
  std::vector<uint32_t> relaxed;
  for (int attempt = 0;; ++attempt) {
    mesh = raw;
    ThinTriangleOptions topt;
    topt.frozen = &frozen;
    tt = remove_thin_triangles(mesh, surface_distance, topt);
    std::vector<char> frozen_now(mesh.vertices.size());
    for (size_t i = 0; i < frozen_now.size(); ++i) frozen_now[i] = frozen[tt.kept[i]];
    RelaxOptions ropt;
    ropt.frozen = &frozen_now;
    relaxed = relax_thin_triangles(mesh, onto_surface, ropt);
    // Changed: a triangle that is not a restricted facet, or is one twice.
    std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> now;
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
      std::array<uint32_t, 3> t;
      for (size_t k = 0; k < 3; ++k) t[k] = tt.kept[mesh.triangles[f][k]];
      std::sort(t.begin(), t.end());
      now.emplace_back(t, f);
    }
    std::sort(now.begin(), now.end());
    std::vector<uint32_t> changed;
    for (size_t k = 0; k < now.size(); ++k)
      if (!std::binary_search(raw_tris.begin(), raw_tris.end(), now[k].first) ||
          (k > 0 && now[k - 1].first == now[k].first) || (k + 1 < now.size() && now[k + 1].first == now[k].first))
        changed.push_back(now[k].second);
    // ... and every triangle around a relaxed vertex.
    std::vector<char> moved(mesh.vertices.size(), 0);
    for (uint32_t v : relaxed) moved[v] = 1;
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
      if (moved[mesh.triangles[f][0]] || moved[mesh.triangles[f][1]] || moved[mesh.triangles[f][2]])
        changed.push_back(f);
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    const auto pairs = intersecting_triangles(mesh, &changed);
    if (pairs.empty()) break;
    stats.cleanup_retries = attempt + 1;
    if (attempt == 2) {
      mesh = raw;
      tt = ThinTriangleStats{};
      relaxed.clear();
      break;
    }
    for (const auto& [a, b] : pairs)
      for (const uint32_t f : {a, b})
        for (uint32_t v : mesh.triangles[f]) frozen[tt.kept[v]] = 1;
  }
  stats.edge_flips = tt.flips;
  stats.edge_collapses = tt.collapses;
  stats.vertices_relaxed = int64_t(relaxed.size());
}

}  // namespace

TriangleMesh restricted_delaunay(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points,
                                 RestrictedDelaunayStats* stats_out, int64_t max_repair_points,
                                 ComputeBackend* backend) {
  const auto t0 = std::chrono::steady_clock::now();
  RestrictedDelaunayStats stats;
  stats.particles = int64_t(points.size());
  if (points.size() < 4) throw InputError("triangulate: fewer than 4 particles");
  if (points.size() >= (size_t(1) << 31)) throw InputError("triangulate: too many particles");
  Triangulation t(s, points, max_repair_points, backend, stats);
  t.delaunay();
  LapTimer timer(t0);
  stats.seconds_delaunay = timer.lap();
  t.make_manifold(timer);
  stats.seconds_repair += timer.lap();
  t.remove_spurious();
  TriangleMesh mesh = t.to_mesh();
  stats.seconds_mesh = timer.lap();
  clean_up(s, mesh, stats);
  stats.seconds_cleanup = timer.lap();
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats_out) *stats_out = stats;
  return mesh;
}

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
