#include "mesh/restricted_delaunay.h"

#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Surface_mesh_default_criteria_3.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>

#include <tbb/parallel_for.h>

#include <chrono>
#include <queue>
#include <unordered_map>

#include "common/error.h"
#include "mesh/thin_triangles.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh {
namespace {

using Tr = CGAL::Surface_mesh_default_triangulation_3;
using C2t3 = CGAL::Complex_2_in_triangulation_3<Tr>;
using GT = Tr::Geom_traits;
using Point = GT::Point_3;
using Surface = CGAL::Implicit_surface_3<GT, std::function<GT::FT(Point)>>;

}  // namespace

int64_t orient_components(TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& outward) {
  auto& tris = mesh.triangles;
  std::unordered_map<uint64_t, std::vector<uint32_t>> faces_of;
  faces_of.reserve(tris.size() * 2);
  for (uint32_t f = 0; f < tris.size(); ++f)
    for (int e = 0; e < 3; ++e) faces_of[edge_key(tris[f][size_t(e)], tris[f][size_t((e + 1) % 3)])].push_back(f);
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
        for (uint32_t g : faces_of[edge_key(a, b)]) {
          if (g == f || comp[g] >= 0) continue;
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

TriangleMesh restricted_delaunay(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points,
                                 RestrictedDelaunayStats* stats_out) {
  const auto t0 = std::chrono::steady_clock::now();
  RestrictedDelaunayStats stats;
  stats.particles = int64_t(points.size());
  if (points.size() < 4) throw InputError("triangulate: fewer than 4 particles");
  Tr tr;
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const auto& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  tr.insert(pts.begin(), pts.end());
  // The bounding sphere holds the data box; the oracle's bisection stops within 5 µm of
  // f = 0 (its bound is relative to the sphere's radius). The crossings it finds place
  // only the repair points; each halving is an evaluation of f, about half of them all.
  const Eigen::Vector3d centre = 0.5 * (s.data_min + s.data_max);
  const double radius = 0.5 * (s.data_max - s.data_min).norm() * 1.1 + 1e-6;
  // f at every Voronoi vertex (finite cell's circumcentre), computed in parallel up
  // front: the mesher's scan tests each Voronoi edge's two ends, and each vertex ends
  // four edges. The oracle looks them up and evaluates only bisection points.
  std::vector<Point> centres;
  centres.reserve(tr.number_of_finite_cells());
  for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c) centres.push_back(tr.dual(c));
  std::vector<double> fc(centres.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, centres.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      fc[i] = mpu::evaluate_f(s, Eigen::Vector3d(centres[i].x(), centres[i].y(), centres[i].z()));
  });
  std::unordered_map<Point, double> cache;
  cache.reserve(centres.size());
  for (size_t i = 0; i < centres.size(); ++i) cache.emplace(centres[i], fc[i]);
  Surface surface(
      [&s, &cache](Point p) {
        const auto it = cache.find(p);
        return it != cache.end() ? it->second : mpu::evaluate_f(s, Eigen::Vector3d(p.x(), p.y(), p.z()));
      },
      GT::Sphere_3(Point(centre.x(), centre.y(), centre.z()), radius * radius), 0.005 / radius);
  // No refinement criterion: only the manifold repair adds points.
  CGAL::Surface_mesh_default_criteria_3<Tr> criteria(0.0, 1e30, 1e30);
  C2t3 c2t3(tr);
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag(), 0);

  // Vertices: the given points that the complex uses, in their order, then the added ones.
  std::unordered_map<Point, int64_t> given;  // position -> input index (inserted as given)
  given.reserve(points.size());
  for (size_t i = 0; i < pts.size(); ++i) given.emplace(pts[i], int64_t(i));
  std::map<Tr::Vertex_handle, uint32_t> index;
  std::vector<std::pair<int64_t, Tr::Vertex_handle>> used;  // (order key, vertex)
  for (auto it = c2t3.facets_begin(); it != c2t3.facets_end(); ++it)
    for (int k = 1; k <= 3; ++k) {
      const Tr::Vertex_handle v = it->first->vertex((it->second + k) & 3);
      if (index.emplace(v, 0).second) {
        const auto g = given.find(v->point());
        used.emplace_back(g != given.end() ? g->second : int64_t(points.size()) + int64_t(used.size()), v);
      }
    }
  std::sort(used.begin(), used.end());
  TriangleMesh mesh;
  for (const auto& [key, v] : used) {
    index[v] = uint32_t(mesh.vertices.size());
    mesh.vertices.emplace_back(v->point().x(), v->point().y(), v->point().z());
    if (key >= int64_t(points.size())) ++stats.repair_points;
  }
  stats.unused_points = int64_t(points.size()) - (int64_t(mesh.vertices.size()) - stats.repair_points);
  for (auto it = c2t3.facets_begin(); it != c2t3.facets_end(); ++it) {
    std::array<uint32_t, 3> t;
    for (int k = 1; k <= 3; ++k) t[size_t(k - 1)] = index[it->first->vertex((it->second + k) & 3)];
    mesh.triangles.push_back(t);
  }
  std::vector<Eigen::Vector3d> outward(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) outward[i] = mpu::evaluate_fg(s, mesh.vertices[i]).g;
  stats.flipped_components = orient_components(mesh, outward);
  // The repair points leave a few thin triangles (mesh/thin_triangles.h).
  const ThinTriangleStats tt = remove_thin_triangles(mesh, [&s](const Eigen::Vector3d& x) {
    const mpu::Sample e = mpu::evaluate_fg(s, x);
    const double g = e.g.norm();
    return g > 0 ? std::abs(e.f) / g : INFINITY;
  });
  stats.edge_flips = tt.flips;
  stats.edge_collapses = tt.collapses;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats_out) *stats_out = stats;
  return mesh;
}

}  // namespace mpumesh
