#include "cgal_mesh3_peer.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>

#include <chrono>
#include <cmath>
#include <map>

#include "mesh/topology.h"

namespace mpumesh::bench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

// Trilinear interpolation of the padded volume in index space (voxel centres at integer
// indices, one voxel of background around): > 0 inside. Meshing runs in index space
// scaled by the spacing (an axis-aligned frame); vertices are mapped to the volume's
// physical frame at the end.
struct Trilinear {
  const Volume* v;
  double iso, background;
  double value(int64_t i, int64_t j, int64_t k) const {
    if (i < 0 || j < 0 || k < 0 || i >= v->dims[0] || j >= v->dims[1] || k >= v->dims[2]) return background;
    return v->at(i, j, k);
  }
  int operator()(const K::Point_3& p) const {
    const double x = p.x() / v->spacing.x(), y = p.y() / v->spacing.y(), z = p.z() / v->spacing.z();
    const int64_t i = int64_t(std::floor(x)), j = int64_t(std::floor(y)), k = int64_t(std::floor(z));
    const double fx = x - double(i), fy = y - double(j), fz = z - double(k);
    double c = 0;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx)
          c += (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz) * value(i + dx, j + dy, k + dz);
    return c >= iso ? 1 : 0;
  }
};

}  // namespace

Mesh3Result cgal_mesh3(const Volume& v, const TriangleMesh& mc, const Mesh3Params& p) {
  const auto t0 = std::chrono::steady_clock::now();
  Mesh3Result r;
  float lo = v.voxels.empty() ? 0.f : v.voxels[0];
  for (float x : v.voxels) lo = std::min(lo, x);
  Trilinear f{&v, p.iso, std::min(double(lo), p.iso - 1000)};
  const Eigen::Vector3d ext = (Eigen::Vector3d(double(v.dims[0]), double(v.dims[1]), double(v.dims[2])) +
                               Eigen::Vector3d::Ones()).cwiseProduct(v.spacing);
  const CGAL::Bbox_3 box(-v.spacing.x(), -v.spacing.y(), -v.spacing.z(), ext.x(), ext.y(), ext.z());
  Domain domain(CGAL::parameters::function = f, CGAL::parameters::bounding_object = box,
                CGAL::parameters::relative_error_bound = 1e-6);
  Criteria criteria(CGAL::parameters::facet_angle = p.facet_angle, CGAL::parameters::facet_size = p.facet_size,
                    CGAL::parameters::facet_distance = p.facet_distance);
  // Initial points on every marching-cubes component: the centroids of up to 24 of its
  // triangles, spread over its list, each snapped onto the domain's surface along the
  // triangle's normal. (With one point per component Mesh_3 lost 16 of the 21 bones, with
  // six 14: a long Voronoi edge crosses a thin bone twice and sees no crossing.) mc is in physical millimetres, the domain in
  // spacing-scaled index space.
  constexpr size_t kPerComponent = 24;
  C3t3 c3t3;
  int64_t ncomp = 0;
  const std::vector<int32_t> comp = triangle_components(mc, &ncomp);
  std::vector<std::vector<size_t>> members(static_cast<size_t>(ncomp));
  for (size_t t = 0; t < mc.triangles.size(); ++t) members[size_t(comp[t])].push_back(t);
  const Eigen::Matrix3d to_index = v.direction.transpose();
  auto construct = domain.construct_intersection_object();
  const double h = v.spacing.minCoeff();
  for (const auto& m : members)
    for (size_t k = 0, count = std::min<size_t>(kPerComponent, m.size()); k < count; ++k) {
      const auto& tri = mc.triangles[m[k * m.size() / count]];
      const Eigen::Vector3d a = mc.vertices[tri[0]], b = mc.vertices[tri[1]], c = mc.vertices[tri[2]];
      const Eigen::Vector3d n = to_index * (b - a).cross(c - a).normalized();
      const Eigen::Vector3d q = to_index * ((a + b + c) / 3 - v.origin);
      const K::Point_3 p0(q.x() - h * n.x(), q.y() - h * n.y(), q.z() - h * n.z());
      const K::Point_3 p1(q.x() + h * n.x(), q.y() + h * n.y(), q.z() + h * n.z());
      const auto hit = construct(K::Segment_3(p0, p1));
      if (std::get<2>(hit) == 0) continue;
      Tr::Vertex_handle vh = c3t3.triangulation().insert(Tr::Weighted_point(std::get<0>(hit)));
      if (vh == Tr::Vertex_handle()) continue;
      c3t3.set_dimension(vh, 2);
      c3t3.set_index(vh, std::get<1>(hit));
      ++r.initial_points;
    }
  CGAL::refine_mesh_3(c3t3, domain, criteria, CGAL::parameters::no_perturb(), CGAL::parameters::no_exude(),
                      CGAL::parameters::manifold());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The boundary facets, oriented outward (from the inside cell).
  std::map<Tr::Vertex_handle, uint32_t> index;
  auto vid = [&](Tr::Vertex_handle h) {
    auto [it, fresh] = index.emplace(h, uint32_t(r.mesh.vertices.size()));
    if (fresh) {
      const auto& pt = h->point().point();
      r.mesh.vertices.push_back(v.origin + v.direction * Eigen::Vector3d(pt.x(), pt.y(), pt.z()));
    }
    return it->second;
  };
  for (auto it = c3t3.facets_in_complex_begin(); it != c3t3.facets_in_complex_end(); ++it) {
    Tr::Cell_handle cell = it->first;
    int i = it->second;
    if (!c3t3.is_in_complex(cell)) {  // use the inside cell's view of the facet
      const Tr::Cell_handle other = cell->neighbor(i);
      i = other->index(cell);
      cell = other;
    }
    // Facet i of a positively oriented cell, counter-clockwise seen from outside the
    // cell: (i+1, i+2, i+3) for odd i, reversed for even i.
    uint32_t a = vid(cell->vertex((i + 1) & 3)), b = vid(cell->vertex((i + 2) & 3)), c = vid(cell->vertex((i + 3) & 3));
    if (i % 2 == 0) std::swap(b, c);
    r.mesh.triangles.push_back({a, b, c});
  }
  // Should the convention above be the other one, the enclosed volume tells.
  double vol = 0;
  for (const auto& t : r.mesh.triangles)
    vol += r.mesh.vertices[t[0]].dot(r.mesh.vertices[t[1]].cross(r.mesh.vertices[t[2]]));
  if (vol < 0)
    for (auto& t : r.mesh.triangles) std::swap(t[1], t[2]);
  return r;
}

}  // namespace mpumesh::bench
