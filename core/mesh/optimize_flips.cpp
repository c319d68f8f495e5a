// Steps 1 and 5 of the mesh optimisation (mesh/mesh_optimize.h): Delaunay flips, and
// flips for smoothness.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <span>
#include <unordered_set>

#include "common/error.h"
#include "geometry/angle.h"
#include "mesh/cgal_geometry.h"
#include "mesh/edge_faces.h"
#include "mesh/optimize_steps.h"
#include "mesh/quality.h"

namespace mpumesh::optimize {
namespace {

// The angle at a of the triangle abc (radians).
double angle_at(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return angle_between(b - a, c - a);
}

// Whether the angles at c and d facing the edge ab add up to less than pi by far more than
// rounding, told from their cosines, without the arc tangents: α + β = π - δ makes
// cos α + cos β = 2 sin(δ / 2) cos((α - β) / 2) <= δ, so a sum above 1e-6 means δ > 1e-6.
// (Most edges are, and the arc tangents would be a tenth of the optimisation's time.)
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

}  // namespace

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

namespace {

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

}  // namespace

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


}  // namespace mpumesh::optimize
