#include "mesh/mesh_optimize.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <span>
#include <unordered_set>

#include "common/error.h"
#include "common/hash.h"
#include "geometry/drop_unused.h"
#include "geometry/tet_mesh.h"
#include "geometry/vertex_faces.h"
#include "mesh/edge_edit.h"
#include "mesh/edge_faces.h"
#include "mesh/cgal_geometry.h"
#include "mesh/quality.h"
#include "mpu/mpu_eval_ref.h"
#include "particles/particle_step_ref.h"

namespace mpumesh {
namespace {

Eigen::Vector3d area_normal(const std::vector<Eigen::Vector3d>& x, const Tri& t) {
  return (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
}

// The angle at a of the triangle abc (radians).
double angle_at(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return angle_between(b - a, c - a);
}

// Whether the angles at c and d facing the edge ab add up to less than pi by far more than
// rounding, told from their cosines, without the arc tangents: α + β = π - δ makes
// cos α + cos β = 2 sin(δ / 2) cos((α - β) / 2) <= δ, so a sum above 1e-6 means δ > 1e-6.
// (On the sample CT most edges are; the arc tangents took 10% of the optimisation's CPU.)
bool clearly_delaunay(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector3d& d) {
  const Eigen::Vector3d ca = a - c, cb = b - c, da = a - d, db = b - d;
  const double cos_c = ca.dot(cb) / std::sqrt(ca.squaredNorm() * cb.squaredNorm());
  const double cos_d = da.dot(db) / std::sqrt(da.squaredNorm() * db.squaredNorm());
  return cos_c + cos_d > 1e-6;
}

// The distance of each point from the surface: |f| (on the backend), which is about the
// distance in mm near f = 0 (mpu_surface.h).
std::vector<double> surface_distances(const mpu::MpuSurface& s, ComputeBackend& backend,
                                      const std::vector<Eigen::Vector3d>& p) {
  std::vector<double> d = backend.mpu_f(s, p);
  for (double& v : d) v = std::abs(v);
  return d;
}

// Undoes the flips `done` that made a face cross another (exact predicates; the faces
// across a thin plate or a rim), and then those whose faces cross one undone; returns how
// many.
int64_t undo_crossing_flips(TriangleMesh& m, const std::vector<FlipRecord>& done) {
  std::vector<uint32_t> changed;  // the faces to check: the flips', then the undone ones'
  for (const FlipRecord& fl : done) changed.insert(changed.end(), {fl.f1, fl.f2});
  int64_t undone = 0;
  for (int round = 0; round < 3 && !changed.empty(); ++round) {
    std::unordered_set<uint32_t> crossing;
    for (const auto& [f, g] : intersecting_triangles(m, &changed)) crossing.insert({f, g});
    changed.clear();
    for (const FlipRecord& fl : done)
      if ((crossing.count(fl.f1) || crossing.count(fl.f2)) && m.triangles[fl.f1] != fl.old1) {
        undo_flip(m.triangles, fl);
        changed.insert(changed.end(), {fl.f1, fl.f2});
        ++undone;
      }
  }
  return undone;
}

// A Delaunay flip (step 1): the edge ab of the faces f1 = abc and f2 = bad becomes cd.
struct DelaunayFlip {
  uint32_t f1, f2;
  Tri n1, n2;
  uint64_t new_edge;
};

// The flip of the quad q's edge, if it is not locally Delaunay and its triangles are
// nearly coplanar (see step 1 in the header).
std::optional<DelaunayFlip> delaunay_flip(const TriangleMesh& m, const EdgeFaces& edges, const EdgeQuad& q,
                                          const OptimizeOptions& opt, const FrozenVertices& frozen) {
  const auto& T = m.triangles;
  const auto& x = m.vertices;
  const auto [f1, f2, a, b, c, d] = q;
  const Tri &t1 = T[f1], &t2 = T[f2];
  const bool delaunay_already = clearly_delaunay(x[a], x[b], x[c], x[d]) ||
                                angle_at(x[c], x[a], x[b]) + angle_at(x[d], x[a], x[b]) <= M_PI + 1e-9;
  if (delaunay_already) return std::nullopt;
  if (!q.may_flip(edges, frozen)) return std::nullopt;
  const Tri n1 = q.flipped1(), n2 = q.flipped2();
  const Eigen::Vector3d o = (area_normal(x, t1).normalized() + area_normal(x, t2).normalized());
  const Eigen::Vector3d m1 = area_normal(x, n1).normalized(), m2 = area_normal(x, n2).normalized();
  if (!(m1.dot(m2) >= std::cos(opt.max_flip_dihedral_deg * M_PI / 180)) || !(m1.dot(o) > 0) || !(m2.dot(o) > 0))
    return std::nullopt;
  return DelaunayFlip{f1, f2, n1, n2, edge_key(c, d)};
}

// The flips that `propose` finds, one or none for each edge with a quad (edge_quad; in
// parallel), in the edges' order; `dist` gets the distances from the surface of each
// one's old edge's midpoint and its new edge's (ab and cd of a flip whose new faces are
// adc and bcd).
template <class Candidate, class Propose>
std::vector<Candidate> flip_candidates(const TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                                       Propose&& propose, std::vector<double>& dist) {
  const auto& x = m.vertices;
  const EdgeFaces edges(m.triangles, true);
  const std::vector<uint64_t>& keys = edges.keys();
  std::vector<std::optional<Candidate>> found(keys.size());
  tbb::parallel_for(size_t(0), keys.size(), [&](size_t i) {
    if (const auto q = edge_quad(m.triangles, edges, i)) found[i] = propose(edges, *q);
  });
  std::vector<Candidate> cand;
  std::vector<Eigen::Vector3d> mids;
  for (const auto& f : found)
    if (f) {
      mids.push_back(0.5 * (x[f->n1[0]] + x[f->n2[0]]));  // ab
      mids.push_back(0.5 * (x[f->n1[1]] + x[f->n1[2]]));  // cd
      cand.push_back(*f);
    }
  dist = surface_distances(s, backend, mids);
  return cand;
}

// Whether candidate i's new edge cd lies no farther from the surface than its old edge
// ab, or than flip_offset of its length (`dist` from flip_candidates).
template <class Candidate>
bool new_edge_near_surface(const std::vector<Eigen::Vector3d>& x, const Candidate& f, const std::vector<double>& dist,
                           size_t i, const OptimizeOptions& opt) {
  const double len = (x[f.n1[1]] - x[f.n1[2]]).norm();  // d - c
  return dist[2 * i + 1] <= std::max(dist[2 * i], opt.flip_offset * len);
}

// The flips of one pass (see the header), applied; returns them.
std::vector<FlipRecord> flip_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                            const OptimizeOptions& opt, const FrozenVertices& frozen) {
  auto& T = m.triangles;
  const auto& x = m.vertices;
  std::vector<double> dist;
  const auto propose = [&](const EdgeFaces& edges, const EdgeQuad& q) {
    return delaunay_flip(m, edges, q, opt, frozen);
  };
  const std::vector<DelaunayFlip> cand = flip_candidates<DelaunayFlip>(m, s, backend, propose, dist);
  std::vector<char> locked(T.size(), 0);
  std::unordered_set<uint64_t> made;
  std::vector<FlipRecord> done;
  for (size_t i = 0; i < cand.size(); ++i) {
    const DelaunayFlip& c = cand[i];
    if (locked[c.f1] || locked[c.f2] || made.count(c.new_edge)) continue;
    if (!new_edge_near_surface(x, c, dist, i, opt)) continue;
    done.push_back(flip_faces(T, c.f1, c.f2, c.n1, c.n2));
    locked[c.f1] = locked[c.f2] = 1;
    made.insert(c.new_edge);
  }
  return done;
}

// The angle between two triangles' normals (any lengths), in degrees.
double normals_angle_deg(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2) {
  return angle_between(n1, n2) * 180 / M_PI;
}

// A smoothing flip (step 5): the edge ab of the faces f1 = abc and f2 = bad becomes cd.
// `near` holds f1, f2 and the four faces across their outer edges.
struct SmoothFlip {
  uint32_t f1, f2;
  Tri n1, n2;
  uint64_t new_edge;
  double gain;  // the fall of the five edges' dihedral sum, degrees
  std::array<uint32_t, 6> near;
};

// The flip of the quad q's edge, if it makes the surface smoother at little cost to the
// shapes (see step 5 in the header).
std::optional<SmoothFlip> smoothing_flip(const TriangleMesh& m, const EdgeFaces& edges, const EdgeQuad& q,
                                         const OptimizeOptions& opt, const FrozenVertices& frozen) {
  const auto& T = m.triangles;
  const auto& x = m.vertices;
  const auto [f1, f2, a, b, c, d] = q;
  const Tri& t1 = T[f1];
  const Eigen::Vector3d o1 = area_normal(x, t1), o2 = area_normal(x, T[f2]);
  // Flatter than the bound by far more than rounding, told from the cosine (most edges
  // are; see clearly_delaunay); else from the angle.
  const double cos_above = std::cos(opt.smooth_flip_above_deg * M_PI / 180);
  if (o1.dot(o2) / std::sqrt(o1.squaredNorm() * o2.squaredNorm()) > cos_above + 1e-6) return std::nullopt;
  const double before = normals_angle_deg(o1, o2);
  if (before < opt.smooth_flip_above_deg) return std::nullopt;
  if (!q.may_flip(edges, frozen)) return std::nullopt;
  const Tri n1 = q.flipped1(), n2 = q.flipped2();
  const Eigen::Vector3d m1 = area_normal(x, n1), m2 = area_normal(x, n2);
  if (!(m1.dot(o1 + o2) > 0) || !(m2.dot(o1 + o2) > 0)) return std::nullopt;
  if (triangle_min_angle_below(x[a], x[d], x[c], opt.min_keep_deg) ||
      triangle_min_angle_below(x[b], x[c], x[d], opt.min_keep_deg))
    return std::nullopt;
  const auto across = [&](uint32_t u, uint32_t v, uint32_t f) {
    const size_t e = edges.find(edge_key(u, v));
    MPUMESH_ASSERT(e != EdgeFaces::npos, "smoothing_flip: no such edge");
    const std::span<const uint32_t> g = edges.faces(e);
    return g.front() == f ? (g.size() > 1 ? g.back() : UINT32_MAX) : g.front();
  };
  // The four outer edges: ca and bc were f1's, ad and db f2's.
  const std::array<uint32_t, 6> near = {f1, f2, across(c, a, f1), across(b, c, f1), across(a, d, f2), across(d, b, f2)};
  if (std::count(near.begin(), near.end(), UINT32_MAX) > 0) return std::nullopt;
  const Eigen::Vector3d nca = area_normal(x, T[near[2]]), nbc = area_normal(x, T[near[3]]);
  const Eigen::Vector3d nad = area_normal(x, T[near[4]]), ndb = area_normal(x, T[near[5]]);
  const std::array<double, 5> was = {before, normals_angle_deg(o1, nca), normals_angle_deg(o1, nbc),
                                     normals_angle_deg(o2, nad), normals_angle_deg(o2, ndb)};
  const std::array<double, 5> now = {normals_angle_deg(m1, m2), normals_angle_deg(m1, nca), normals_angle_deg(m2, nbc),
                                     normals_angle_deg(m1, nad), normals_angle_deg(m2, ndb)};
  // No sharper fold than there was: a fold near 180° would hold a flat tetrahedron in a
  // volume mesh.
  if (*std::max_element(now.begin(), now.end()) > *std::max_element(was.begin(), was.end())) return std::nullopt;
  const double gain = std::accumulate(was.begin(), was.end(), 0.0) - std::accumulate(now.begin(), now.end(), 0.0);
  if (!(gain > opt.smooth_flip_gain_deg)) return std::nullopt;
  const double shape_loss = triangle_radius_ratio(x[a], x[b], x[c]) + triangle_radius_ratio(x[b], x[a], x[d]) -
                            triangle_radius_ratio(x[a], x[d], x[c]) - triangle_radius_ratio(x[b], x[c], x[d]);
  if (shape_loss > opt.smooth_flip_shape_per_deg * gain) return std::nullopt;
  return SmoothFlip{f1, f2, n1, n2, edge_key(c, d), gain, near};
}

// The flips of one pass of step 5, applied; returns how many were kept.
int64_t smoothing_flip_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                            const OptimizeOptions& opt, const FrozenVertices& frozen) {
  auto& T = m.triangles;
  const auto& x = m.vertices;
  std::vector<double> dist;
  const auto propose = [&](const EdgeFaces& edges, const EdgeQuad& q) {
    return smoothing_flip(m, edges, q, opt, frozen);
  };
  const std::vector<SmoothFlip> cand = flip_candidates<SmoothFlip>(m, s, backend, propose, dist);
  // The largest gains first; a face and its neighbours take one flip a pass (the gains
  // were reckoned with the neighbours as they were), and the new edge must lie as near
  // the surface as the old one, as in step 1.
  std::vector<size_t> order(cand.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t i, size_t j) { return cand[i].gain > cand[j].gain; });
  std::vector<char> locked(T.size(), 0);
  std::unordered_set<uint64_t> made;
  std::vector<FlipRecord> done;
  for (size_t i : order) {
    const SmoothFlip& f = cand[i];
    if (made.count(f.new_edge) || std::any_of(f.near.begin(), f.near.end(), [&](uint32_t g) { return locked[g]; }))
      continue;
    if (!new_edge_near_surface(x, f, dist, i, opt)) continue;
    done.push_back(flip_faces(T, f.f1, f.f2, f.n1, f.n2));
    for (uint32_t g : f.near) locked[g] = 1;
    made.insert(f.new_edge);
  }
  return int64_t(done.size()) - undo_crossing_flips(m, done);
}

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

// Step 4's first part (see the header): each vertex of three triangles whose tetrahedron
// with its three neighbours has a dihedral angle under flat_cap_deg is removed, the
// triangle of its neighbours taking its three, where that triangle is no triangle yet,
// each neighbour keeps three triangles and the triangle's smallest angle is at least the
// three's, or polish_below_deg. The three triangles' area vectors add up to the new
// one's, so it faces as they did. Returns how many (each a vertex and two triangles
// fewer); the removed vertex stays in the list, used by no triangle.
int64_t remove_flat_caps(TriangleMesh& m, const OptimizeOptions& opt, const FrozenVertices& frozen) {
  auto& T = m.triangles;
  const auto& x = m.vertices;
  const auto vf = vertex_faces(m);
  std::vector<char> locked(x.size(), 0), gone(T.size(), 0);
  int64_t done = 0;
  for (uint32_t v = 0; v < x.size(); ++v) {
    if (vf[v].size() != 3 || frozen[v] || locked[v]) continue;
    // The ring a, b, c in the order of v's triangles (v, a, b), (v, b, c), (v, c, a).
    const Tri& first = T[vf[v][0]];
    const int i = int(std::find(first.begin(), first.end(), v) - first.begin());
    const uint32_t a = first[size_t((i + 1) % 3)], b = first[size_t((i + 2) % 3)];
    uint32_t c = UINT32_MAX;
    for (uint32_t f : vf[v])
      for (uint32_t w : T[f])
        if (w != v && w != a && w != b) c = w;
    const Tri merged = {a, b, c};
    if (c == UINT32_MAX ||
        std::any_of(merged.begin(), merged.end(), [&](uint32_t w) { return frozen[w] || locked[w] || vf[w].size() <= 3; }))
      continue;
    const std::array<double, 6> dihedral = dihedral_angles(x[v], x[a], x[b], x[c]);
    if (!(*std::min_element(dihedral.begin(), dihedral.end()) < opt.flat_cap_deg)) continue;
    const double angle = triangle_min_angle_deg(x[a], x[b], x[c]);
    if (!(angle >= std::min(opt.polish_below_deg, smallest_angle(x, T, vf[v])))) continue;
    bool exists = false;  // abc already a triangle (a speck of four vertices)
    for (uint32_t f : vf[a])
      exists = exists || (std::count(T[f].begin(), T[f].end(), b) && std::count(T[f].begin(), T[f].end(), c) &&
                          !std::count(T[f].begin(), T[f].end(), v));
    if (exists) continue;
    T[vf[v][0]] = merged;
    gone[vf[v][1]] = gone[vf[v][2]] = 1;
    locked[v] = locked[a] = locked[b] = locked[c] = 1;
    ++done;
  }
  drop_gone_faces(T, gone);
  return done;
}

// Step 4's places for each vertex of `verts` (kPlaces each, in order): its neighbours'
// mean, then 12 directions at 5, 15 and 30% of its shortest edge, all in its tangent plane
// (the mean of its triangles' normals), then put on f = 0 on the backend.
constexpr int kDirections = 12;
constexpr double kSteps[] = {0.05, 0.15, 0.3};
constexpr size_t kPlaces = 1 + kDirections * std::size(kSteps);
particles::ParticleState polish_places(const TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                                       const std::vector<double>& spacing, const OptimizeOptions& opt,
                                       const VertexFaces& vf, const std::vector<uint32_t>& verts) {
  const auto& T = m.triangles;
  const auto& x = m.vertices;
  particles::ParticleState st;
  st.resize(verts.size() * kPlaces);
  for (size_t i = 0; i < verts.size(); ++i) {
    const uint32_t v = verts[i];
    Eigen::Vector3d nrm = Eigen::Vector3d::Zero(), mean = Eigen::Vector3d::Zero();
    double shortest = INFINITY;
    int count = 0;
    for (uint32_t f : vf[v]) {
      nrm += area_normal(x, T[f]);
      for (uint32_t w : T[f])
        if (w != v) mean += x[w], ++count, shortest = std::min(shortest, (x[w] - x[v]).norm());
    }
    nrm.normalize();
    const Eigen::Vector3d u = nrm.unitOrthogonal(), w = nrm.cross(u);
    size_t k = i * kPlaces;
    const Eigen::Vector3d to_mean = mean / count - x[v];
    st.x[k++] = x[v] + to_mean - to_mean.dot(nrm) * nrm;
    for (double step : kSteps)
      for (int d = 0; d < kDirections; ++d) {
        const double a = 2 * M_PI * d / kDirections;
        st.x[k++] = x[v] + step * shortest * (std::cos(a) * u + std::sin(a) * w);
      }
    for (size_t j = i * kPlaces; j < k; ++j) st.sigma[j] = spacing[v];
  }
  project_onto_surface(s, backend, st, opt);
  return st;
}

// Step 4 (see the header): each vertex of a triangle still under polish_below_deg takes,
// of its places (polish_places), the one that most raises the smallest angle around it,
// turning no triangle by more than max_turn_deg; one vertex after another. Returns the
// moves made.
int64_t polish_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                    const std::vector<double>& spacing, const OptimizeOptions& opt, const FrozenVertices& frozen) {
  const auto& T = m.triangles;
  auto& x = m.vertices;
  std::vector<uint32_t> verts;
  for (const Tri& t : T)
    if (triangle_min_angle_below(x[t[0]], x[t[1]], x[t[2]], opt.polish_below_deg))
      for (uint32_t v : t)
        if (!frozen[v]) verts.push_back(v);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  if (verts.empty()) return 0;
  const auto vf = vertex_faces(m);
  const particles::ParticleState st = polish_places(m, s, backend, spacing, opt, vf, verts);
  const double cos_turn = std::cos(opt.max_turn_deg * M_PI / 180);
  int64_t moved = 0;
  for (size_t i = 0; i < verts.size(); ++i) {
    const uint32_t v = verts[i];
    const Eigen::Vector3d home = x[v];
    std::vector<Eigen::Vector3d> normals;
    for (uint32_t f : vf[v]) normals.push_back(area_normal(x, T[f]));
    double best = smallest_angle(x, T, vf[v]);
    Eigen::Vector3d best_at = home;
    for (size_t j = i * kPlaces; j < (i + 1) * kPlaces; ++j) {
      if (!landed(st, j)) continue;
      x[v] = st.x[j];
      bool ok = true;
      for (size_t q = 0; q < vf[v].size() && ok; ++q) ok = turned_within(normals[q], area_normal(x, T[vf[v][q]]), cos_turn);
      const double angle = ok ? smallest_angle(x, T, vf[v]) : -1;
      if (angle > best + 1e-9) best = angle, best_at = x[v];
    }
    x[v] = best_at;
    moved += best_at != home;
  }
  return moved;
}

// The rounds' counts set to zero (before the rounds, and when none of them is kept).
void clear_counts(OptimizeStats& st) {
  st.rounds = 0, st.flips = 0, st.moves = 0, st.collapses = 0, st.polish_moves = 0, st.smooth_flips = 0;
}

// The rounds, with the vertices `frozen` left as they are.
void optimize_rounds(TriangleMesh& mesh, const mpu::MpuSurface& s, ComputeBackend& backend,
                     const std::vector<double>& spacing, const OptimizeOptions& opt, const FrozenVertices& frozen,
                     OptimizeStats& st) {
  clear_counts(st);
  for (int round = 0; round < opt.rounds; ++round) {
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
                            const std::vector<double>& spacing, const OptimizeOptions& opt) {
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
    optimize_rounds(mesh, s, backend, spacing, opt, frozen, st);
    const auto pairs = intersecting_triangles(mesh);
    if (pairs.empty()) break;
    st.retries = attempt + 1;
    if (attempt == 2) {
      mesh = input;
      clear_counts(st);
      break;
    }
    for (const auto& [a, b] : pairs)
      for (uint32_t f : {a, b})
        for (uint32_t v : mesh.triangles[f]) st.frozen += frozen.freeze(v);
  }
  if (st.collapses > 0) drop_unused_points(mesh.vertices, mesh.triangles);
  st.after = shape_figures(mesh);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

}  // namespace mpumesh
