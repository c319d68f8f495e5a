#include "points/mesh_points.h"

namespace mpumesh::pts {

PointCloud mesh_points(const TriangleMesh& mesh, bool centroids) {
  PointCloud out;
  std::vector<Eigen::Vector3d> vn(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d n2 = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);  // 2 x area x normal
    const double len = n2.norm();
    if (!(len > 0)) continue;
    for (uint32_t v : t) vn[v] += n2;
    if (!centroids) continue;
    out.positions.push_back((a + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3);
    out.normals.push_back(n2 / len);
  }
  for (size_t v = 0; v < vn.size(); ++v) {
    const double len = vn[v].norm();
    if (!(len > 0)) continue;
    out.positions.push_back(mesh.vertices[v]);
    out.normals.push_back(vn[v] / len);
  }
  return out;
}

}  // namespace mpumesh::pts
