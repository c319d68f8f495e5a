// Stage 7: the restricted Delaunay triangulation of the particles on the MPU surface
// (DESIGN.md "Triangulation"): the Delaunay facets of the particles whose dual Voronoi
// edge crosses f = 0, the crossing found by bisection on f. CGAL's surface mesher does
// exactly this over a triangulation that already holds the particles; with its
// Manifold_tag it adds a point (the Voronoi edge's crossing) only where the sample is too
// thin for a manifold, and retriangulates there. The triangles are oriented consistently
// through their shared edges, each component outward by ∇f; then edge collapses and flips
// remove most thin triangles (mesh/thin_triangles.h).
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "mpu/mpu_surface.h"

namespace mpumesh {

struct RestrictedDelaunayStats {
  int64_t particles = 0;       // points given
  int64_t repair_points = 0;   // points CGAL added for a manifold
  int64_t unused_points = 0;   // given points on no restricted facet (dropped)
  int64_t flipped_components = 0;
  int64_t edge_flips = 0, edge_collapses = 0;  // thin triangles removed (mesh/thin_triangles.h)
  double seconds = 0;
};

// The mesh's vertices are the used particles (in their given order), then the repair
// points (less those that edge collapses merged away).
TriangleMesh restricted_delaunay(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points,
                                 RestrictedDelaunayStats* stats = nullptr);

// Orients the triangles of each edge-connected component consistently (breadth-first
// through shared edges; the mesh must be manifold) and then each component so that its
// normals agree with `outward` (one direction per vertex) by an area-weighted vote.
// Returns the number of components flipped.
int64_t orient_components(TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& outward);

}  // namespace mpumesh
