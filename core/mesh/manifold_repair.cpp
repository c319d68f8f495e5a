// The manifold repair of the restricted Delaunay triangulation (docs/method.md
// "Triangulation"), as CGAL's surface mesher does with its Manifold_tag, but bounded and
// repeatable: while some edge has more than two restricted facets or some vertex more
// than one fan, each such element gets a point where the Voronoi edge of its largest
// facet (the one whose surface Delaunay ball, centred on that crossing, is widest)
// crosses f = 0; a facet far wider than the sampling around it gets its crossing too.
// The cells the new points replace are evaluated and the facets found again, round by
// round; then the lost sheets (mesh/lost_sheets.cpp), and the repair again around them.
#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>
#include <string>
#include <unordered_map>

#include "common/error.h"
#include "mesh/delaunay_state.h"
#include "mesh/edge_faces.h"

namespace mpumesh::delaunay {
namespace {

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

// The facets around each non-manifold edge (more than two facets) and around each
// non-manifold vertex (its facets form more than one fan), one group per element; only
// elements at a vertex marked in `check` (which must list every facet at those vertices).
std::vector<std::vector<uint32_t>> non_manifold_groups(const std::vector<RFacet>& facets,
                                                       const std::vector<char>& check) {
  std::vector<std::vector<uint32_t>> groups;
  const EdgeFaces edges(facets.size(), [&](size_t f) -> const std::array<uint32_t, 3>& { return facets[f].v; });
  for (size_t e = 0; e < edges.size(); ++e) {
    const uint64_t key = edges.keys()[e];
    const std::span<const uint32_t> around = edges.faces(e);
    if (around.size() > 2 && (check[uint32_t(key >> 32)] || check[uint32_t(key)]))
      groups.emplace_back(around.begin(), around.end());
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

}  // namespace

bool Triangulation::repair_round(int round, LapTimer& timer, const std::function<void(size_t)>& told) {
  touched.assign(points.size() + repair.size(), 0);
  stats.seconds_repair += timer.lap();
  evaluate_new_cells(s, dt, touched, backend, round == 0 ? nullptr : &inserted);
  stats.seconds_evaluate += timer.lap();
  facets = round == 0 ? restricted_facets(dt) : restricted_facets_near(dt, touched);
  const std::vector<std::vector<uint32_t>> groups = non_manifold_groups(facets, touched);
  const std::vector<std::pair<uint32_t, double>> wide = oversized_facets(facets, touched, touched.size());
  told(groups.size() + wide.size());
  if (groups.empty() && wide.empty()) return true;
  if (repair.size() >= max_repair || round >= 100) {
    const RFacet& at = facets[groups.empty() ? wide[0].first : groups[0][0]];
    const Eigen::Vector3d where = vec(at.cell->vertex((at.i + 1) & 3)->point());
    throw NumericalError(fmt::format("triangulate: {} non-manifold edges or vertices and {} wide facets remain after {} "
                                     "repair points in {} rounds, one at ({:.1f}, {:.1f}, {:.1f}) mm: the particles are "
                                     "too sparse for this surface (ask for more)",
                                     groups.size(), wide.size(), repair.size(), round, where.x(), where.y(),
                                     where.z()));
  }
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

// Manifold repair, as CGAL's surface mesher does with its Manifold_tag, but bounded and
// repeatable: while some edge has more than two restricted facets or some vertex more
// than one fan, each such element gets a point where the Voronoi edge of its largest
// facet (the one whose surface Delaunay ball, centred on that crossing, is widest)
// crosses f = 0; the cells that the new points replace are evaluated, and the facets
// found again.
void Triangulation::make_manifold(LapTimer& timer, const ProgressFn& progress) {
  int round = 0;
  size_t first = 0;  // the first round's elements to repair
  const auto told = [&](size_t left) {
    if (first == 0) first = left;
    tell(progress, 0.5 + 0.3 * std::max(0.0, 1 - double(left) / double(std::max<size_t>(first, 1))));
  };
  for (int pass = 0;; ++pass) {  // the manifold repair, then lost sheets (below)
    while (!repair_round(round, timer, told)) ++round;
    // Lost sheets, twice at most, each time followed by the manifold repair around the
    // new points.
    facets = restricted_facets(dt);
    if (pass == 2 || !add_sheet_points()) break;
    ++round;
  }
}

}  // namespace mpumesh::delaunay
