#include "mesh/thin_triangles.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "geometry/drop_unused.h"
#include "geometry/vertex_faces.h"
#include "mesh/edge_edit.h"
#include "mesh/quality.h"

namespace mpumesh {
namespace {

Eigen::Vector3d normal(const TriangleMesh& m, const std::array<uint32_t, 3>& t) {
  return (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
}

double min_angle(const TriangleMesh& m, const std::array<uint32_t, 3>& t) {
  return triangle_min_angle_deg(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
}

// min_angle(m, t) < deg (triangle_min_angle_below).
bool below(const TriangleMesh& m, const std::array<uint32_t, 3>& t, double deg) {
  return triangle_min_angle_below(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], deg);
}

// Whether the collapse of the edge uv (u merged into v) is a needle's: its ends share
// exactly the edge's two faces and the link condition holds, the collapse leaves no face
// twice, and no face around u that stays turns by more than max_dihedral_deg.
bool may_collapse(const TriangleMesh& mesh, const VertexFaces& vf, const std::vector<char>& dead, uint32_t u,
                  uint32_t v, double cos_turn) {
  const auto& tris = mesh.triangles;
  int shared_faces = 0;
  for (uint32_t g : vf[u])
    if (!dead[g] && (tris[g][0] == v || tris[g][1] == v || tris[g][2] == v)) ++shared_faces;
  const auto link = collapse_link(vertex_ring(tris, vf[u], u, &dead), vertex_ring(tris, vf[v], v, &dead));
  if (shared_faces != 2 || !link) return false;
  // The link condition's edge part: triangles u a b and v a b (a, b the two common
  // neighbours) must not both exist, or the collapse leaves v a b twice (a pillow).
  auto has_face = [&](uint32_t x) {
    for (uint32_t g : vf[x]) {
      if (dead[g]) continue;
      int hit = 0;
      for (uint32_t w : tris[g]) hit += w == (*link)[0] || w == (*link)[1];
      if (hit == 2) return true;
    }
    return false;
  };
  if (has_face(u) && has_face(v)) return false;
  // The faces around u that stay must not turn.
  for (uint32_t g : vf[u]) {
    if (dead[g] || tris[g][0] == v || tris[g][1] == v || tris[g][2] == v) continue;
    std::array<uint32_t, 3> moved = tris[g];
    for (uint32_t& w : moved)
      if (w == u) w = v;
    const Eigen::Vector3d n_new = (mesh.vertices[moved[1]] - mesh.vertices[moved[0]])
                                      .cross(mesh.vertices[moved[2]] - mesh.vertices[moved[0]]);
    if (!(n_new.norm() > 0) || !(n_new.normalized().dot(normal(mesh, tris[g])) > cos_turn)) return false;
  }
  return true;
}

// One pass of collapses; returns how many.
int64_t collapse_pass(TriangleMesh& mesh, const ThinTriangleOptions& opt) {
  auto& tris = mesh.triangles;
  const size_t nv = mesh.vertices.size();
  const VertexFaces vf = vertex_faces(mesh);  // the faces of each vertex before the pass
  std::vector<char> locked(nv, 0), dead(tris.size(), 0);
  const double cos_turn = std::cos(opt.max_dihedral_deg * M_PI / 180);
  int64_t n = 0;
  for (uint32_t f = 0; f < tris.size(); ++f) {
    if (dead[f] || !below(mesh, tris[f], opt.below_deg)) continue;
    const auto& t = tris[f];
    double len[3];
    for (int e = 0; e < 3; ++e) len[e] = (mesh.vertices[t[size_t((e + 1) % 3)]] - mesh.vertices[t[size_t(e)]]).norm();
    const int e = int(std::min_element(len, len + 3) - len);
    if (3 * len[e] > std::min(len[(e + 1) % 3], len[(e + 2) % 3])) continue;  // not a needle
    uint32_t u = t[size_t(e)], v = t[size_t((e + 1) % 3)];
    if (u < v) std::swap(u, v);  // keep the earlier vertex (a particle before a repair point)
    if (locked[u] || locked[v]) continue;
    bool frozen = false;
    for (uint32_t g : vf[u])
      if (!dead[g]) frozen = frozen || opt.frozen.any_of(tris[g]);
    if (frozen || !may_collapse(mesh, vf, dead, u, v, cos_turn)) continue;
    collapse_edge(tris, vf[u], v, u, dead);
    for (uint32_t g : vf[u])
      for (uint32_t w : tris[g]) locked[w] = 1;
    for (uint32_t g : vf[v])
      for (uint32_t w : tris[g]) locked[w] = 1;
    ++n;
  }
  drop_gone_faces(tris, dead);
  return n;
}

int64_t flip_passes(TriangleMesh& mesh, const std::function<double(const Eigen::Vector3d&)>& surface_distance,
                    const ThinTriangleOptions& opt);

}  // namespace

ThinTriangleStats remove_thin_triangles(TriangleMesh& mesh,
                                        const std::function<double(const Eigen::Vector3d&)>& surface_distance,
                                        const ThinTriangleOptions& opt) {
  ThinTriangleStats st;
  for (int pass = 0; pass < opt.max_passes; ++pass) {
    const int64_t c = collapse_pass(mesh, opt);
    st.collapses += c;
    if (c == 0) break;
  }
  st.flips = flip_passes(mesh, surface_distance, opt);
  st.kept = drop_unused_points(mesh.vertices, mesh.triangles);
  return st;
}

namespace {

// The faces of each vertex, kept up to date through the flips (an edge map of vectors,
// rebuilt per pass, takes far longer); each list allocated once at its size.
class LiveVertexFaces {
 public:
  explicit LiveVertexFaces(const TriangleMesh& mesh) : tris_(mesh.triangles), vf_(mesh.vertices.size()) {
    const VertexFaces rows = vertex_faces(mesh);
    for (size_t v = 0; v < vf_.size(); ++v) vf_[v].assign(rows[v].begin(), rows[v].end());
  }
  // The faces with edge uv: up to 3 of them in `out`, and how many in all.
  int edge_faces(uint32_t u, uint32_t v, uint32_t out[3]) const {
    int n = 0;
    for (uint32_t g : vf_[u])
      if (tris_[g][0] == v || tris_[g][1] == v || tris_[g][2] == v) {
        if (n < 3) out[n] = g;
        ++n;
      }
    return n;
  }
  // The flip of quad q made: a leaves f2, b leaves f1, c joins f2, d joins f1.
  void flipped(const EdgeQuad& q) {
    drop(vf_[q.a], q.f2);
    drop(vf_[q.b], q.f1);
    vf_[q.c].push_back(q.f2);
    vf_[q.d].push_back(q.f1);
  }

 private:
  static void drop(std::vector<uint32_t>& list, uint32_t f) { list.erase(std::find(list.begin(), list.end(), f)); }
  const std::vector<Tri>& tris_;
  std::vector<std::vector<uint32_t>> vf_;
};

// The quad of face f's edge e (f = abc, its neighbour bad running b -> a), when the edge
// has two faces, the flip's new edge cd is no edge yet and no vertex is frozen.
std::optional<EdgeQuad> flippable_quad(const TriangleMesh& mesh, const LiveVertexFaces& vf, uint32_t f, int e,
                                       const FrozenVertices& frozen) {
  const auto& tris = mesh.triangles;
  const uint32_t a = tris[f][size_t(e)], b = tris[f][size_t((e + 1) % 3)], c = tris[f][size_t((e + 2) % 3)];
  uint32_t ab[3];
  if (vf.edge_faces(a, b, ab) != 2) return std::nullopt;
  const uint32_t g = ab[0] == f ? ab[1] : ab[0];
  // g runs b -> a (consistent orientation); d is its third vertex.
  uint32_t d = UINT32_MAX;
  for (int k = 0; k < 3; ++k)
    if (tris[g][size_t(k)] == b && tris[g][size_t((k + 1) % 3)] == a) d = tris[g][size_t((k + 2) % 3)];
  uint32_t cd[3];
  if (d == UINT32_MAX || d == c || vf.edge_faces(c, d, cd) > 0) return std::nullopt;
  if (frozen[a] || frozen[b] || frozen[c] || frozen[d]) return std::nullopt;
  return EdgeQuad{f, g, a, b, c, d};
}

// Whether flipping q to the faces cad and dbc raises the smaller of the two faces' minimum
// angles, keeps the quad nearly flat and brings the edge no farther from the surface.
bool flip_mends(const TriangleMesh& mesh, const EdgeQuad& q, const std::array<uint32_t, 3>& t1,
                const std::array<uint32_t, 3>& t2,
                const std::function<double(const Eigen::Vector3d&)>& surface_distance, const ThinTriangleOptions& opt) {
  const auto& tris = mesh.triangles;
  const double cos_dihedral = std::cos(opt.max_dihedral_deg * M_PI / 180);
  const double before = std::min(min_angle(mesh, tris[q.f1]), min_angle(mesh, tris[q.f2]));
  const double after = std::min(min_angle(mesh, t1), min_angle(mesh, t2));
  if (after <= before + 1e-9) return false;
  const Eigen::Vector3d n_old = (normal(mesh, tris[q.f1]) + normal(mesh, tris[q.f2])).normalized();
  const Eigen::Vector3d n1 = normal(mesh, t1), n2 = normal(mesh, t2);
  if (!(n1.dot(n2) > cos_dihedral && n1.dot(n_old) > cos_dihedral && n2.dot(n_old) > cos_dihedral)) return false;
  // The new edge may lie off the surface by its sagitta, no more than the old one's.
  const double old_off = surface_distance(0.5 * (mesh.vertices[q.a] + mesh.vertices[q.b]));
  return surface_distance(0.5 * (mesh.vertices[q.c] + mesh.vertices[q.d])) <= std::max(opt.max_offset_mm, old_off);
}

int64_t flip_passes(TriangleMesh& mesh, const std::function<double(const Eigen::Vector3d&)>& surface_distance,
                    const ThinTriangleOptions& opt) {
  auto& tris = mesh.triangles;
  LiveVertexFaces vf(mesh);
  int64_t flips = 0;
  for (int pass = 0; pass < opt.max_passes; ++pass) {
    int64_t pass_flips = 0;
    for (uint32_t f = 0; f < tris.size(); ++f) {
      if (!below(mesh, tris[f], opt.below_deg)) continue;
      for (int e = 0; e < 3; ++e) {
        const auto q = flippable_quad(mesh, vf, f, e, opt.frozen);
        if (!q) continue;
        const std::array<uint32_t, 3> t1{q->c, q->a, q->d}, t2{q->d, q->b, q->c};  // abc + bad -> cad + dbc
        if (!flip_mends(mesh, *q, t1, t2, surface_distance, opt)) continue;
        flip_faces(tris, q->f1, q->f2, t1, t2);
        vf.flipped(*q);
        ++pass_flips;
        break;  // f changed; its other edges wait for the next pass
      }
    }
    flips += pass_flips;
    if (pass_flips == 0) break;
  }
  return flips;
}

}  // namespace

std::vector<uint32_t> relax_thin_triangles(TriangleMesh& mesh,
                                           const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& project,
                                           const RelaxOptions& opt) {
  const VertexFaces vf = vertex_faces(mesh);
  auto fan_min = [&](uint32_t v) {
    double a = 180;
    for (uint32_t f : vf[v]) a = std::min(a, min_angle(mesh, mesh.triangles[f]));
    return a;
  };
  auto raw_normal = [&](uint32_t f) {
    const auto& t = mesh.triangles[f];
    return Eigen::Vector3d((mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]));
  };
  const double cos_turn = std::cos(opt.max_turn_deg * M_PI / 180);
  std::vector<uint32_t> out;
  // The triangles to look at: all at first, then those around the last round's vertices
  // (a move changes only the triangles around the vertex moved).
  std::vector<uint32_t> look(mesh.triangles.size());
  for (uint32_t f = 0; f < look.size(); ++f) look[f] = f;
  for (int round = 0; round < opt.rounds; ++round) {
    // The vertices of this round's thin triangles, in index order.
    std::vector<uint32_t> todo;
    for (const uint32_t f : look)
      if (below(mesh, mesh.triangles[f], opt.below_deg))
        todo.insert(todo.end(), mesh.triangles[f].begin(), mesh.triangles[f].end());
    std::sort(todo.begin(), todo.end());
    todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
    look.clear();
    for (const uint32_t v : todo) look.insert(look.end(), vf[v].begin(), vf[v].end());
    std::sort(look.begin(), look.end());
    look.erase(std::unique(look.begin(), look.end()), look.end());
    int64_t round_moves = 0;
    for (const uint32_t v : todo) {
      if (opt.frozen[v]) continue;
      const double before = fan_min(v);
      if (before >= opt.below_deg) continue;
      std::vector<uint32_t> ring;
      for (uint32_t f : vf[v])
        for (uint32_t w : mesh.triangles[f])
          if (w != v) ring.push_back(w);
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (uint32_t w : ring) centre += mesh.vertices[w];
      centre /= double(ring.size());
      const Eigen::Vector3d old = mesh.vertices[v];
      std::vector<Eigen::Vector3d> n_old;
      for (uint32_t f : vf[v]) n_old.push_back(raw_normal(f).normalized());
      bool ok = false;
      for (const double step : {1.0, 0.5, 0.25}) {
        const Eigen::Vector3d x = project(old + step * (centre - old));
        if (!x.allFinite()) continue;
        mesh.vertices[v] = x;
        ok = fan_min(v) > before;
        for (size_t k = 0; ok && k < vf[v].size(); ++k) {
          const Eigen::Vector3d n = raw_normal(vf[v][k]);
          ok = n.norm() > 0 && n.normalized().dot(n_old[k]) > cos_turn;
        }
        if (ok) break;
      }
      if (!ok) {
        mesh.vertices[v] = old;
        continue;
      }
      ++round_moves;
      out.push_back(v);
    }
    if (round_moves == 0) break;
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace mpumesh
