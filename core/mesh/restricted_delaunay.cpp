#include "mesh/restricted_delaunay.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "common/error.h"
#include "common/kd_tree.h"
#include "common/lap_timer.h"
#include "compute/compute_backend.h"
#include "mesh/delaunay_state.h"
#include "mesh/orientation.h"
#include "mesh/spurious_components.h"
#include "mesh/triangulation_cleanup.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh {
namespace delaunay {

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

}  // namespace delaunay

using delaunay::Triangulation;

TriangleMesh restricted_delaunay(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points,
                                 RestrictedDelaunayStats* stats_out, int64_t max_repair_points,
                                 ComputeBackend* backend, const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  RestrictedDelaunayStats stats;
  stats.particles = int64_t(points.size());
  if (points.size() < 4) throw InputError("triangulate: fewer than 4 particles");
  if (points.size() >= (size_t(1) << 31)) throw InputError("triangulate: too many particles");
  Triangulation t(s, points, max_repair_points, backend, stats);
  t.delaunay();
  LapTimer timer(t0);
  stats.seconds_delaunay = timer.lap();
  tell(progress, 0.5);
  t.make_manifold(timer, progress);
  stats.seconds_repair += timer.lap();
  tell(progress, 0.8);
  t.remove_spurious();
  TriangleMesh mesh = t.to_mesh();
  stats.seconds_mesh = timer.lap();
  clean_up_triangulation(s, mesh, stats);
  stats.seconds_cleanup = timer.lap();
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats_out) *stats_out = stats;
  tell(progress, 1);
  return mesh;
}

}  // namespace mpumesh
