#include "cgal_remesh_peer.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace mpumesh::bench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh to_cgal(const TriangleMesh& m) {
  std::vector<K::Point_3> points;
  points.reserve(m.vertices.size());
  for (const auto& v : m.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(m.triangles.size());
  for (const auto& t : m.triangles) faces.push_back({t[0], t[1], t[2]});
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces)) throw std::runtime_error("the input is not a polygon mesh");
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, faces, sm);
  return sm;
}

TriangleMesh from_cgal(const SurfaceMesh& sm) {
  TriangleMesh m;
  std::unordered_map<uint32_t, uint32_t> index;
  for (auto v : sm.vertices()) {
    const auto& p = sm.point(v);
    index[uint32_t(v)] = uint32_t(m.vertices.size());
    m.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : sm.faces()) {
    std::array<uint32_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[size_t(k++)] = index.at(uint32_t(v));
    m.triangles.push_back(t);
  }
  return m;
}

RemeshResult remesh(const TriangleMesh& input, double edge, int iterations) {
  const auto t0 = std::chrono::steady_clock::now();
  SurfaceMesh sm = to_cgal(input);
  PMP::isotropic_remeshing(faces(sm), edge, sm, CGAL::parameters::number_of_iterations(iterations));
  sm.collect_garbage();
  RemeshResult r;
  r.mesh = from_cgal(sm);
  r.edge_length = edge;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace

RemeshResult cgal_isotropic_remesh(const TriangleMesh& input, int64_t triangles, int iterations) {
  double area = 0;
  for (const auto& t : input.triangles)
    area += 0.5 * (input.vertices[t[1]] - input.vertices[t[0]]).cross(input.vertices[t[2]] - input.vertices[t[0]]).norm();
  const double first = std::sqrt(4 * area / (std::sqrt(3.0) * double(triangles)));
  const RemeshResult trial = remesh(input, first, iterations);
  return remesh(input, first * std::sqrt(double(trial.mesh.triangles.size()) / double(triangles)), iterations);
}

}  // namespace mpumesh::bench
