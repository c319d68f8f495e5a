// The benchmark's strongest peer: CGAL Mesh_3 on the gray image, as the time target names it:
// CGAL's gray-image domain (trilinear interpolation, inside above iso) on the volume
// padded by one voxel of background, started by CGAL's initialisation for images (a
// seed in every connected component of the thresholded image; with CGAL's random start
// it misses whole bones); facet_angle 30 and the given facet size and distance;
// manifold() on. Sequential (CGAL's default), or in CGAL's parallel mode (Parallel_tag,
// TBB, on as many threads as ours), which a user with two or more cores would choose.
#pragma once

#include "geometry/tet_mesh.h"
#include "geometry/triangle_mesh.h"
#include "volume/volume.h"

namespace mpumesh::bench {

struct Mesh3Params {
  double iso = 226;
  // A label map instead (labels 1-255, background 0): CGAL's labelled-image domain and
  // its initialisation for labelled images; iso is not used.
  bool labels = false;
  double facet_angle = 30, facet_size = 3.4, facet_distance = 0.72;
  // A volume mesh too: cell_size > 0 adds the cell criteria (that size, radius-edge ratio
  // 3), then CGAL's sliver perturbation and exudation.
  double cell_size = 0;
  // manifold() on (off: a complex where several labels meet, non-manifold along its
  // junctions by nature, which manifold() would refine without end).
  bool manifold = true;
  // The least facet distance cgal_mesh3_matching sets (mm).
  double min_facet_distance = 0;
  // CGAL's parallel mode (Parallel_tag) on TBB's threads.
  bool parallel = false;
};

struct Mesh3Result {
  // The facets in the complex, each oriented out of its higher subdomain's cell; for a
  // label map, face_labels holds each facet's two subdomains (0 outside), lower first.
  TriangleMesh mesh;
  TetMesh volume;  // with cell_size: the cells in the complex, one region (a label map's: a region per label)
  int64_t initial_points = 0;  // after the initialisation
  double seconds = 0;  // domain, initial points and refinement
};

Mesh3Result cgal_mesh3(const Volume& v, const Mesh3Params& p);
// The same in parallel mode, whatever p.parallel says.
Mesh3Result cgal_mesh3_parallel(const Volume& v, const Mesh3Params& p);

// Mesh_3 with its facet size set so that it makes about as many triangles as `ours`
// (distance 0.2 × the size, at least min_facet_distance): a first size from our mean edge, one correction, since the
// count goes as 1 / size². `p` returns the size and distance used.
Mesh3Result cgal_mesh3_matching(const Volume& v, Mesh3Params& p, const TriangleMesh& ours);

}  // namespace mpumesh::bench
