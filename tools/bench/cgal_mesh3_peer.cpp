#include "cgal_mesh3_peer.h"

#include <algorithm>
#include <cmath>

#include "cgal_mesh3_run.h"

namespace mpumesh::bench {

Mesh3Result cgal_mesh3(const Volume& v, const Mesh3Params& p) {
  return p.parallel ? cgal_mesh3_parallel(v, p) : mesh3::run<CGAL::Sequential_tag>(v, p);
}

Mesh3Result cgal_mesh3_matching(const Volume& v, Mesh3Params& p, const TriangleMesh& ours) {
  double edge = 0;
  for (const auto& t : ours.triangles) edge += (ours.vertices[t[0]] - ours.vertices[t[1]]).norm();
  const double count = double(std::max<size_t>(1, ours.triangles.size()));
  p.facet_size = 1.2 * edge / count;
  p.facet_distance = std::max(0.2 * p.facet_size, p.min_facet_distance);
  const Mesh3Result first = cgal_mesh3(v, p);
  p.facet_size *= std::sqrt(double(first.mesh.triangles.size()) / count);
  p.facet_distance = std::max(0.2 * p.facet_size, p.min_facet_distance);
  return cgal_mesh3(v, p);
}

}  // namespace mpumesh::bench
