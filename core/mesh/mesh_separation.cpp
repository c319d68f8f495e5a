#include "mesh/mesh_separation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <map>
#include <set>

#include "mesh/cgal_geometry.h"

namespace mpumesh {
namespace {

Eigen::AlignedBox3d bounding_box(const TriangleMesh& m) {
  Eigen::AlignedBox3d b;
  for (const auto& v : m.vertices) b.extend(v);
  return b;
}

Eigen::Vector3d face_normal(const TriangleMesh& m, uint32_t f) {
  const auto& t = m.triangles[f];
  return (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
}

// The triangles around each vertex.
std::vector<std::vector<uint32_t>> vertex_triangles(const TriangleMesh& m) {
  std::vector<std::vector<uint32_t>> out(m.vertices.size());
  for (uint32_t f = 0; f < m.triangles.size(); ++f)
    for (const uint32_t v : m.triangles[f]) out[v].push_back(f);
  return out;
}

struct Move {
  uint32_t vertex;
  Eigen::Vector3d to;
};

// Where the vertices of `a` that are inside `f`, or on a triangle crossing it, go: an inside
// vertex to its closest point on `f` and `margin` beyond; a crossing triangle's outside
// vertices inward along their normal, past the deepest vertex of `f` that pokes through
// the triangle's plane, and `margin` more.
std::vector<Move> moves_out_of(const TriangleMesh& a, const TriangleMesh& f, double margin,
                               const std::vector<std::vector<uint32_t>>& around, int64_t& crossings) {
  const auto pairs = crossing_pairs(a, f);
  crossings += int64_t(pairs.size());
  std::map<uint32_t, double> push;  // a crossing triangle's vertex: how far inward
  for (const auto& [ta, tf] : pairs) {
    const auto& t = a.triangles[ta];
    const Eigen::Vector3d n = face_normal(a, ta).normalized();
    double depth = 0;
    for (const uint32_t q : f.triangles[tf]) depth = std::max(depth, -(f.vertices[q] - a.vertices[t[0]]).dot(n));
    for (const uint32_t v : t) push[v] = std::max(push[v], depth + margin);
  }
  Eigen::AlignedBox3d box = bounding_box(f);
  box.min().array() -= margin;
  box.max().array() += margin;
  std::vector<uint32_t> ids;
  std::vector<Eigen::Vector3d> pts;
  for (uint32_t v = 0; v < a.vertices.size(); ++v)
    if (push.count(v) || box.contains(a.vertices[v])) ids.push_back(v), pts.push_back(a.vertices[v]);
  const std::vector<ClosestOnMesh> near = closest_and_inside(pts, f);
  std::vector<Move> moves;
  for (size_t k = 0; k < ids.size(); ++k) {
    const Eigen::Vector3d& p = pts[k];
    const Eigen::Vector3d& c = near[k].point;
    const double d = (p - c).norm();
    if (near[k].inside && d > 0) {
      moves.push_back({ids[k], c + margin * (c - p) / d});
    } else if (const auto it = push.find(ids[k]); it != push.end()) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      for (const uint32_t t : around[ids[k]]) n += face_normal(a, t);
      if (n.norm() > 0) moves.push_back({ids[k], p - it->second * n.normalized()});
    }
  }
  return moves;
}

// Undoes the moves that flip a triangle or make `a` cross itself; returns how many.
int64_t undo_bad_moves(TriangleMesh& a, const std::vector<Move>& moves, const std::vector<Eigen::Vector3d>& before,
                       const std::vector<std::vector<uint32_t>>& around) {
  std::set<uint32_t> moved;
  for (const Move& m : moves) moved.insert(m.vertex);
  std::set<uint32_t> reverted;
  auto revert = [&](uint32_t v) {
    if (moved.count(v) && reverted.insert(v).second) a.vertices[v] = before[v];
  };
  std::vector<uint32_t> touched;
  for (const uint32_t v : moved) touched.insert(touched.end(), around[v].begin(), around[v].end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  TriangleMesh old;  // the triangles' orientation before the moves
  old.triangles = a.triangles;
  old.vertices = before;
  for (bool again = true; again;) {
    again = false;
    for (const uint32_t t : touched)
      if (face_normal(a, t).dot(face_normal(old, t)) <= 0)
        for (const uint32_t v : a.triangles[t])
          if (moved.count(v) && !reverted.count(v)) revert(v), again = true;
    if (again) continue;
    for (const auto& [s, t] : intersecting_triangles(a, &touched))
      for (const uint32_t f : {s, t})
        for (const uint32_t v : a.triangles[f])
          if (moved.count(v) && !reverted.count(v)) revert(v), again = true;
  }
  return int64_t(reverted.size());
}

}  // namespace

bool bounding_boxes_overlap(const TriangleMesh& a, const TriangleMesh& b) {
  return bounding_box(a).intersects(bounding_box(b));
}

SeparationStats separate_from(TriangleMesh& a, const std::vector<const TriangleMesh*>& fixed, double margin,
                              int max_rounds) {
  SeparationStats s;
  const std::vector<std::vector<uint32_t>> around = vertex_triangles(a);
  const std::vector<Eigen::Vector3d> start = a.vertices;
  std::vector<size_t> near;  // indices into `fixed`
  for (size_t k = 0; k < fixed.size(); ++k)
    if (bounding_boxes_overlap(a, *fixed[k])) near.push_back(k);
  s.crossings_with.assign(fixed.size(), 0);
  std::set<uint32_t> moved;
  for (;; ++s.rounds) {
    int64_t crossings = 0;
    std::vector<Move> moves;
    for (const size_t k : near) {
      int64_t with = 0;
      std::vector<Move> m = moves_out_of(a, *fixed[k], margin, around, with);
      moves.insert(moves.end(), m.begin(), m.end());
      s.crossings_with[k] = with;
      crossings += with;
    }
    if (s.rounds == 0) s.crossings_before = crossings;
    s.crossings_after = crossings;
    if (crossings == 0 || s.rounds == max_rounds) break;
    const std::vector<Eigen::Vector3d> before = a.vertices;
    for (const Move& m : moves) a.vertices[m.vertex] = m.to;
    s.reverted_vertices += undo_bad_moves(a, moves, before, around);
    for (const Move& m : moves)
      if (a.vertices[m.vertex] != before[m.vertex]) moved.insert(m.vertex);
  }
  s.moved_vertices = int64_t(moved.size());
  for (const uint32_t v : moved) s.max_move_mm = std::max(s.max_move_mm, (a.vertices[v] - start[v]).norm());
  return s;
}

}  // namespace mpumesh
