// Builds the marching-cubes table from face rules: on each face, segments join the
// crossing points so that every inside corner region is cut off (ambiguous faces separate
// the inside corners); the segments are directed so that each loop runs counter-clockwise
// seen from the outside region, chained into loops, and each loop is triangulated as a fan
// whose diagonals avoid joining two points of one face (a diagonal that runs along a face
// could be repeated by the neighbouring cube and give an edge with four triangles).
#include "mc/mc_table.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "common/error.h"

namespace mpumesh::mc {
namespace {

// Faces as corner rings; the ring's edges are looked up from kEdgeCorners.
constexpr std::array<std::array<int, 4>, 6> kFaceCorners = {{
    {0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 2, 6, 5}}};
constexpr std::array<std::array<int, 3>, 6> kFaceNormal = {{
    {0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}}};

Eigen::Vector3d corner_pos(int c) {
  return Eigen::Vector3d(kCorner[c][0], kCorner[c][1], kCorner[c][2]);
}
Eigen::Vector3d edge_mid(int e) {
  return 0.5 * (corner_pos(kEdgeCorners[e][0]) + corner_pos(kEdgeCorners[e][1]));
}
int edge_between(int a, int b) {
  for (int e = 0; e < 12; ++e)
    if ((kEdgeCorners[e][0] == a && kEdgeCorners[e][1] == b) ||
        (kEdgeCorners[e][0] == b && kEdgeCorners[e][1] == a))
      return e;
  MPUMESH_ASSERT(false, "corners are not adjacent");
}
bool on_face(int e, int f) {
  const auto& fc = kFaceCorners[f];
  auto in = [&](int c) { return c == fc[0] || c == fc[1] || c == fc[2] || c == fc[3]; };
  return in(kEdgeCorners[e][0]) && in(kEdgeCorners[e][1]);
}
bool share_face(int e1, int e2) {
  for (int f = 0; f < 6; ++f)
    if (on_face(e1, f) && on_face(e2, f)) return true;
  return false;
}

CubeCase build_case(int config) {
  auto inside = [&](int c) { return (config >> c) & 1; };
  std::array<int, 12> next;
  next.fill(-1);
  for (int f = 0; f < 6; ++f) {
    const auto& fc = kFaceCorners[f];
    const Eigen::Vector3d nf(kFaceNormal[f][0], kFaceNormal[f][1], kFaceNormal[f][2]);
    // Cut off each maximal run of inside corners around the ring. With two inside corners
    // on a diagonal these are two runs: the separating resolution.
    int start = -1;
    for (int i = 0; i < 4; ++i)
      if (!inside(fc[i]) && inside(fc[(i + 1) % 4])) start = i;
    if (start < 0) continue;  // face all inside or all outside
    for (int s = 0; s < 4; ++s) {
      int i = (start + s) % 4;
      if (inside(fc[i]) || !inside(fc[(i + 1) % 4])) continue;
      // A run of inside corners begins at i+1; find where it ends.
      int j = (i + 1) % 4;
      Eigen::Vector3d in_sum = Eigen::Vector3d::Zero();
      int run = 0;
      while (inside(fc[j])) {
        in_sum += corner_pos(fc[j]);
        ++run;
        j = (j + 1) % 4;
      }
      int prev_j = (j + 3) % 4;
      int ea = edge_between(fc[i], fc[(i + 1) % 4]);
      int eb = edge_between(fc[prev_j], fc[j]);
      Eigen::Vector3d mid = 0.5 * (edge_mid(ea) + edge_mid(eb));
      Eigen::Vector3d u = mid - in_sum / run;  // from the inside run toward the outside
      Eigen::Vector3d d = edge_mid(eb) - edge_mid(ea);
      if (d.dot(u.cross(nf)) < 0) std::swap(ea, eb);
      MPUMESH_ASSERT(next[ea] < 0, "two segments leave one crossing point");
      next[ea] = eb;
    }
  }
  CubeCase out;
  std::array<bool, 12> used{};
  std::vector<int8_t> tris;
  for (int e0 = 0; e0 < 12; ++e0) {
    if (next[e0] < 0 || used[e0]) continue;
    std::vector<int> loop;
    for (int e = e0; !used[e]; e = next[e]) {
      used[e] = true;
      loop.push_back(e);
      MPUMESH_ASSERT(next[e] >= 0, "open loop in marching-cubes case");
    }
    const int n = int(loop.size());
    // Pick the fan apex whose diagonals never join two points of one face.
    int apex = 0;
    for (int a = 0; a < n; ++a) {
      bool ok = true;
      for (int k = 2; k < n - 1 && ok; ++k) ok = !share_face(loop[a], loop[(a + k) % n]);
      if (ok) {
        apex = a;
        break;
      }
    }
    for (int k = 1; k + 1 < n; ++k) {
      // The segments run counter-clockwise seen from outside (inside corners on their
      // right), so the fan keeps the loop order.
      tris.push_back(int8_t(loop[apex]));
      tris.push_back(int8_t(loop[(apex + k) % n]));
      tris.push_back(int8_t(loop[(apex + k + 1) % n]));
    }
  }
  MPUMESH_ASSERT(tris.size() <= out.edges.size(), "too many triangles in one cube");
  out.triangle_count = int(tris.size() / 3);
  for (size_t i = 0; i < tris.size(); ++i) out.edges[i] = tris[i];
  return out;
}

}  // namespace

const std::array<CubeCase, 256>& case_table() {
  static const std::array<CubeCase, 256> table = [] {
    std::array<CubeCase, 256> t;
    for (int c = 0; c < 256; ++c) t[size_t(c)] = build_case(c);
    return t;
  }();
  return table;
}

}  // namespace mpumesh::mc
