// The mesh measurements that need CGAL (kept in one file for compile time): intersecting
// triangle pairs within a mesh or between two, and distances from one surface to another.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

// Pairs of triangles that intersect other than through shared vertices or edges
// (CGAL Polygon_mesh_processing::self_intersections on the triangle soup).
int64_t count_self_intersections(const TriangleMesh& mesh);
// The intersecting pairs (i < j) themselves, in order; with `among`, only pairs in which at
// least one triangle is listed; without `adjacent`, only pairs that share no vertex (those
// that share one can cross only where the mesh folds onto itself).
std::vector<std::pair<uint32_t, uint32_t>> intersecting_triangles(const TriangleMesh& mesh,
                                                                 const std::vector<uint32_t>* among = nullptr,
                                                                 bool adjacent = true);

// The intersecting pairs (adjacent ones included) with a triangle among `changed` that
// `was` (the same triangles, before some vertices moved) did not have.
std::vector<std::pair<uint32_t, uint32_t>> new_intersections(const TriangleMesh& now, const TriangleMesh& was,
                                                             const std::vector<uint32_t>& changed);

// Pairs (triangle of `a`, triangle of `b`) that meet, sorted: two meshes that should not
// touch, such as two labels' surfaces.
std::vector<std::pair<uint32_t, uint32_t>> crossing_pairs(const TriangleMesh& a, const TriangleMesh& b);
int64_t count_crossings(const TriangleMesh& a, const TriangleMesh& b);

// Each point's closest point on the closed mesh `to`, and whether the point lies inside
// it (the parity of a ray's crossings).
struct ClosestOnMesh {
  Eigen::Vector3d point;
  bool inside = false;
};
std::vector<ClosestOnMesh> closest_and_inside(const std::vector<Eigen::Vector3d>& points, const TriangleMesh& to);

// Distance (mm) from sample points of `from` to the surface `to`, with each sample's
// area weight: per triangle its three vertices' area share and three interior points.
struct DistanceSamples {
  std::vector<double> distance, weight;
};
DistanceSamples sample_distances(const TriangleMesh& from, const TriangleMesh& to);

// Distance (mm) from each point to the surface `to`.
std::vector<double> point_distances(const std::vector<Eigen::Vector3d>& points, const TriangleMesh& to);

}  // namespace mpumesh
