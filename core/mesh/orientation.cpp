#include "mesh/orientation.h"

#include <queue>

#include "geometry/vertex_faces.h"

namespace mpumesh {

int64_t orient_components(TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& outward) {
  auto& tris = mesh.triangles;
  // The faces of each vertex (compressed rows, cheaper than an edge map of vectors). The
  // faces of edge ab are those of a that hold b.
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

}  // namespace mpumesh
