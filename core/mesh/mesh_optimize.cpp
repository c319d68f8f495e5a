#include "mesh/mesh_optimize.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <span>
#include <unordered_set>

#include "geometry/drop_unused.h"
#include "geometry/vertex_faces.h"
#include "mesh/edge_edit.h"
#include "mesh/optimize_steps.h"
#include "mesh/cgal_geometry.h"
#include "mesh/quality.h"
#include "particles/particle_step_ref.h"

namespace mpumesh {
namespace optimize {

// Whether a triangle whose normal was old_n (of any length) and is new_n after a change is
// still a triangle, turned by no more than acos(cos_turn).
bool turned_within(const Eigen::Vector3d& old_n, const Eigen::Vector3d& new_n, double cos_turn) {
  return new_n.norm() > 0 && old_n.normalized().dot(new_n.normalized()) >= cos_turn;
}

// The points of `st` onto f = 0 on the backend: opt.newton_steps Newton steps, each
// moving a point at most its sigma.
void project_onto_surface(const mpu::MpuSurface& s, ComputeBackend& backend, particles::ParticleState& st,
                          const OptimizeOptions& opt) {
  particles::StepParams p;
  p.newton_steps = opt.newton_steps;
  backend.particle_project(s, st, p, false);
}

// Whether point i of a projection reached f = 0 (within a thousandth of its sigma).
bool landed(const particles::ParticleState& st, size_t i) {
  return std::isfinite(st.distance[i]) && std::abs(st.distance[i]) < 1e-3 * st.sigma[i];
}

// The smallest angle (degrees) of the triangles `faces` with the vertices at x.
double smallest_angle(const std::vector<Eigen::Vector3d>& x, const std::vector<Tri>& T,
                      std::span<const uint32_t> faces) {
  double m = 180;
  for (uint32_t f : faces) m = std::min(m, triangle_min_angle_deg(x[T[f][0]], x[T[f][1]], x[T[f][2]]));
  return m;
}

// Whether moving the vertices to `now` (from `was`) keeps v's triangles: none turns by
// more than max_turn_deg, and the smallest angle around v does not fall, or stays above
// min_keep_deg.
bool move_keeps(const std::vector<Eigen::Vector3d>& was, const std::vector<Eigen::Vector3d>& now,
                const std::vector<Tri>& T, std::span<const uint32_t> faces, const OptimizeOptions& opt) {
  const double cos_turn = std::cos(opt.max_turn_deg * M_PI / 180);
  for (uint32_t f : faces)
    if (!turned_within(area_normal(was, T[f]), area_normal(now, T[f]), cos_turn)) return false;
  // The smallest angle after is at least min_keep_deg when no triangle is below it.
  const bool keeps = std::none_of(faces.begin(), faces.end(), [&](uint32_t f) {
    return triangle_min_angle_below(now[T[f][0]], now[T[f][1]], now[T[f][2]], opt.min_keep_deg);
  });
  return keeps || smallest_angle(now, T, faces) >= smallest_angle(was, T, faces);
}


namespace {

// One relaxation pass (see the header); returns the vertices that moved.
std::vector<uint32_t> relax_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                                 const std::vector<double>& spacing, const VertexFaces& vf,
                                 const OptimizeOptions& opt, const FrozenVertices& frozen) {
  const auto& T = m.triangles;
  const std::vector<Eigen::Vector3d> was = m.vertices;
  const size_t n = was.size();
  // Each triangle's centroid and weight (area / s², s its vertices' mean target).
  std::vector<Eigen::Vector3d> centroid(T.size());
  std::vector<double> weight(T.size());
  tbb::parallel_for(size_t(0), T.size(), [&](size_t f) {
    const Tri& t = T[f];
    centroid[f] = (was[t[0]] + was[t[1]] + was[t[2]]) / 3;
    const double sp = (spacing[t[0]] + spacing[t[1]] + spacing[t[2]]) / 3;
    weight[f] = 0.5 * area_normal(was, t).norm() / (sp * sp);
  });
  // The centroids, within each vertex's tangent plane (the mean of its triangles'
  // normals), then onto f = 0 on the backend.
  particles::ParticleState st;
  st.resize(n);
  tbb::parallel_for(size_t(0), n, [&](size_t v) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), nrm = Eigen::Vector3d::Zero();
    double w = 0;
    for (uint32_t f : vf[v]) c += weight[f] * centroid[f], w += weight[f], nrm += area_normal(was, T[f]);
    Eigen::Vector3d step = w > 0 ? Eigen::Vector3d(c / w - was[v]) : Eigen::Vector3d::Zero();
    if (nrm.norm() > 0) nrm.normalize(), step -= step.dot(nrm) * nrm;
    st.x[v] = was[v] + step;
    st.sigma[v] = spacing[v];  // each Newton step moves at most this far
  });
  project_onto_surface(s, backend, st, opt);
  std::vector<Eigen::Vector3d> now = was;
  std::vector<char> moving(n, 0);
  for (size_t v = 0; v < n; ++v)
    if (!frozen[v] && !vf[v].empty() && landed(st, v) && st.x[v].allFinite()) now[v] = st.x[v], moving[v] = 1;
  // Keep the moves that keep their triangles, against the others' new places; a move
  // given up is tested against again by its neighbours, until none changes.
  std::vector<uint32_t> retest;
  for (uint32_t v = 0; v < n; ++v)
    if (moving[v]) retest.push_back(v);
  for (int loop = 0; loop < 8 && !retest.empty(); ++loop) {
    std::vector<char> fail(retest.size(), 0);
    tbb::parallel_for(size_t(0), retest.size(), [&](size_t k) {
      const uint32_t v = retest[k];
      fail[k] = moving[v] && !move_keeps(was, now, T, vf[v], opt);
    });
    std::vector<uint32_t> next;
    for (size_t k = 0; k < retest.size(); ++k) {
      if (!fail[k]) continue;
      const uint32_t v = retest[k];
      moving[v] = 0;
      now[v] = was[v];
      for (uint32_t f : vf[v])
        for (uint32_t w : T[f])
          if (moving[w]) next.push_back(w);
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    retest.swap(next);
  }
  for (uint32_t v : retest) moving[v] = 0, now[v] = was[v];  // still undecided: stay
  m.vertices = now;
  std::vector<uint32_t> moved;
  for (uint32_t v = 0; v < n; ++v)
    if (moving[v]) moved.push_back(v);
  return moved;
}

// The shortest edge of each triangle under min_keep_deg, the poorest triangle's first,
// each edge once.
std::vector<uint64_t> poor_edges(const TriangleMesh& m, const OptimizeOptions& opt) {
  const auto& x = m.vertices;
  std::vector<std::pair<double, uint64_t>> poor;
  for (const Tri& t : m.triangles) {
    if (!triangle_min_angle_below(x[t[0]], x[t[1]], x[t[2]], opt.min_keep_deg)) continue;
    const double angle = triangle_min_angle_deg(x[t[0]], x[t[1]], x[t[2]]);
    int k = 0;
    for (int e = 1; e < 3; ++e)
      if ((x[t[size_t(e)]] - x[t[size_t((e + 1) % 3)]]).norm() < (x[t[size_t(k)]] - x[t[size_t((k + 1) % 3)]]).norm()) k = e;
    poor.push_back({angle, edge_key(t[size_t(k)], t[size_t((k + 1) % 3)])});
  }
  std::sort(poor.begin(), poor.end());
  std::vector<uint64_t> edges;
  std::unordered_set<uint64_t> seen;
  for (const auto& [angle, key] : poor)
    if (seen.insert(key).second) edges.push_back(key);
  return edges;
}

// Where the merged vertex of the edge ab goes, of `places`: the one that keeps every
// triangle of `keep` (b renamed a) within max_turn_deg of its old normal and gives the
// largest smallest angle, when that beats `before`; nothing otherwise.
std::optional<Eigen::Vector3d> best_merge_place(const std::vector<Eigen::Vector3d>& x, const std::vector<Tri>& T,
                                                const std::vector<uint32_t>& keep, uint32_t a, uint32_t b,
                                                const std::vector<Eigen::Vector3d>& places, double before,
                                                const OptimizeOptions& opt) {
  const double cos_turn = std::cos(opt.max_turn_deg * M_PI / 180);
  double best = before;
  std::optional<Eigen::Vector3d> best_at;
  for (const Eigen::Vector3d& at : places) {
    double worst = 180;
    for (uint32_t f : keep) {
      Eigen::Vector3d p[3];
      for (int k = 0; k < 3; ++k) p[k] = T[f][size_t(k)] == a || T[f][size_t(k)] == b ? at : x[T[f][size_t(k)]];
      if (!turned_within(area_normal(x, T[f]), (p[1] - p[0]).cross(p[2] - p[0]), cos_turn)) {
        worst = -1;
        break;
      }
      worst = std::min(worst, triangle_min_angle_deg(p[0], p[1], p[2]));
    }
    if (worst > best + 1e-9) best = worst, best_at = at;
  }
  return best_at;
}

// Step 2 of a round (see the header): the poor triangles' shortest edges collapsed;
// returns how many. The removed vertex stays in the list, used by no triangle.
int64_t collapse_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                      const std::vector<double>& spacing, const OptimizeOptions& opt, const FrozenVertices& frozen) {
  auto& T = m.triangles;
  auto& x = m.vertices;
  const std::vector<uint64_t> edges = poor_edges(m, opt);
  if (edges.empty()) return 0;
  auto ends = [&](size_t i) { return std::pair{uint32_t(edges[i] >> 32), uint32_t(edges[i] & 0xffffffffu)}; };
  // The edges' midpoints on f = 0 (on the backend).
  particles::ParticleState mid;
  mid.resize(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    const auto [a, b] = ends(i);
    mid.x[i] = 0.5 * (x[a] + x[b]);
    mid.sigma[i] = 0.5 * (spacing[a] + spacing[b]);
  }
  project_onto_surface(s, backend, mid, opt);
  const auto vf = vertex_faces(m);
  auto ring_of = [&](uint32_t v) { return vertex_ring(T, vf[v], v); };
  std::vector<char> locked(x.size(), 0), gone(T.size(), 0);
  int64_t done = 0;
  for (size_t i = 0; i < edges.size(); ++i) {
    const auto [a, b] = ends(i);
    const std::vector<uint32_t> na = ring_of(a), nb = ring_of(b);
    const auto link = collapse_link(na, nb);
    std::vector<uint32_t> ring = na;
    ring.insert(ring.end(), nb.begin(), nb.end());
    // The link condition, the edge's two opposite vertices each keeping three
    // neighbours, nothing frozen around and nothing near an earlier collapse of this pass.
    if (!link || ring_of((*link)[0]).size() <= 3 || ring_of((*link)[1]).size() <= 3 || na.size() + nb.size() < 7)
      continue;
    if (std::any_of(ring.begin(), ring.end(), [&](uint32_t v) { return locked[v] || frozen[v]; })) continue;
    std::vector<uint32_t> faces(vf[a].begin(), vf[a].end()), keep;
    faces.insert(faces.end(), vf[b].begin(), vf[b].end());
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    for (uint32_t f : faces)
      if (std::count(T[f].begin(), T[f].end(), a) + std::count(T[f].begin(), T[f].end(), b) < 2) keep.push_back(f);
    std::vector<Eigen::Vector3d> places;  // the midpoint on f = 0 first, then the ends
    if (landed(mid, i)) places.push_back(mid.x[i]);
    places.push_back(x[a]);
    places.push_back(x[b]);
    const auto at = best_merge_place(x, T, keep, a, b, places, smallest_angle(x, T, faces), opt);
    if (!at) continue;
    collapse_edge(T, vf[b], a, b, gone);
    x[a] = *at;
    for (uint32_t v : ring) locked[v] = 1;
    ++done;
  }
  drop_gone_faces(T, gone);
  return done;
}

// The rounds' counts set to zero (before the rounds, and when none of them is kept).
void clear_counts(OptimizeStats& st) {
  st.rounds = 0, st.flips = 0, st.moves = 0, st.collapses = 0, st.polish_moves = 0, st.smooth_flips = 0;
}

// The rounds, with the vertices `frozen` left as they are.
void optimize_rounds(TriangleMesh& mesh, const mpu::MpuSurface& s, ComputeBackend& backend,
                     const std::vector<double>& spacing, const OptimizeOptions& opt, const FrozenVertices& frozen,
                     OptimizeStats& st, const ProgressFn& progress) {
  clear_counts(st);
  for (int round = 0; round < opt.rounds; ++round) {
    tell(progress, double(round) / opt.rounds);
    st.flips += int64_t(flip_pass(mesh, s, backend, opt, frozen).size());
    if (round >= opt.rounds - opt.smooth_flip_rounds)
      st.smooth_flips += smoothing_flip_pass(mesh, s, backend, opt, frozen);
    st.collapses += collapse_pass(mesh, s, backend, spacing, opt, frozen);
    st.moves += int64_t(relax_pass(mesh, s, backend, spacing, vertex_faces(mesh), opt, frozen).size());
    ++st.rounds;
  }
  if (opt.rounds > 0) st.collapses += remove_flat_caps(mesh, opt, frozen);
  for (int pass = 0; opt.rounds > 0 && pass < opt.polish_passes; ++pass) {
    const int64_t moved = polish_pass(mesh, s, backend, spacing, opt, frozen);
    st.polish_moves += moved;
    if (moved == 0) break;
  }
}

}  // namespace
}  // namespace optimize

ShapeFigures shape_figures(const TriangleMesh& m) {
  ShapeFigures s;
  if (m.triangles.empty()) return s;
  double sum_rr = 0, min_angle = 180;
  int64_t below = 0;
  for (const Tri& t : m.triangles) {
    const double a = triangle_min_angle_deg(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    min_angle = std::min(min_angle, a);
    below += a < 30;
    sum_rr += triangle_radius_ratio(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
  }
  s.min_angle_deg = min_angle;
  s.pct_below_30 = 100.0 * double(below) / double(m.triangles.size());
  s.radius_ratio = sum_rr / double(m.triangles.size());
  return s;
}

OptimizeStats optimize_mesh(TriangleMesh& mesh, const mpu::MpuSurface& s, ComputeBackend& backend,
                            const std::vector<double>& spacing, const OptimizeOptions& opt,
                            const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  OptimizeStats st;
  st.before = shape_figures(mesh);
  const TriangleMesh input = mesh;
  // A flip or a move can make a triangle cross another (across a thin plate); such
  // triangles are found once the rounds are done (exact predicates), and the rounds are
  // done again with their vertices frozen; after three tries, none is kept.
  FrozenVertices frozen(mesh.vertices.size());
  for (int attempt = 0;; ++attempt) {
    mesh = input;
    optimize::optimize_rounds(mesh, s, backend, spacing, opt, frozen, st, progress);
    const auto pairs = intersecting_triangles(mesh);
    if (pairs.empty()) break;
    st.retries = attempt + 1;
    if (attempt == 2) {
      mesh = input;
      optimize::clear_counts(st);
      break;
    }
    for (const auto& [a, b] : pairs)
      for (uint32_t f : {a, b})
        for (uint32_t v : mesh.triangles[f]) st.frozen += frozen.freeze(v);
  }
  if (st.collapses > 0) drop_unused_points(mesh.vertices, mesh.triangles);
  st.after = shape_figures(mesh);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  tell(progress, 1);
  return st;
}

}  // namespace mpumesh

