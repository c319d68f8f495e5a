// The benchmark's strongest peer: CGAL Mesh_3 on the gray image, as issue 5 specifies it.
// The domain is the trilinear interpolation of the volume padded by one voxel of
// background (what CGAL's gray-image domain does), inside where the value is >= iso;
// initial surface points on every connected component of the marching-cubes surface
// (with CGAL's random start it misses whole bones); facet_angle 30 and the given facet size and
// distance; manifold() on. Sequential (CGAL's default build).
#pragma once

#include "mesh/triangle_mesh.h"
#include "volume/volume.h"

namespace mpumesh::bench {

struct Mesh3Params {
  double iso = 226;
  double facet_angle = 30, facet_size = 2.35, facet_distance = 0.3;
};

struct Mesh3Result {
  TriangleMesh mesh;
  int64_t initial_points = 0;
  double seconds = 0;  // domain, initial points and refinement
};

// `mc` is the marching-cubes surface of the same volume and iso-value (its components
// give the initial points).
Mesh3Result cgal_mesh3(const Volume& v, const TriangleMesh& mc, const Mesh3Params& p);

}  // namespace mpumesh::bench
