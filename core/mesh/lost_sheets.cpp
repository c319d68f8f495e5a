// Lost sheets of the restricted Delaunay triangulation: where a thin plate passes whole
// through a particle's Voronoi cell, the particle gets no restricted facet and the plate
// drops out of the mesh; a point on the plate's other side puts it back.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "geometry/vertex_faces.h"
#include "mesh/delaunay_state.h"

namespace mpumesh::delaunay {
namespace {

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
  // would go to p itself and put a point next to its particle (a 0° triangle).
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

}  // namespace mpumesh::delaunay
