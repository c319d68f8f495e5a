// The clean-up after the restricted Delaunay triangulation: the repair points leave a few
// thin triangles, which collapses and flips remove and vertex moves mend
// (mesh/thin_triangles.h). The restricted Delaunay facets are faces of one
// tetrahedralization, so no two of them intersect; a collapse, flip or moved vertex can
// make a triangle that cuts another (across a thin plate). Such changes are found (the
// changed triangles against all, exact predicates) and the clean-up is done again with
// their vertices frozen; after three tries, none is kept.
#pragma once

#include "geometry/triangle_mesh.h"
#include "mesh/restricted_delaunay.h"
#include "mpu/mpu_surface.h"

namespace mpumesh {

// Cleans `mesh` (the triangulation's, on the surface s) and records its counts in stats
// (edge_flips, edge_collapses, vertices_relaxed, cleanup_retries).
void clean_up_triangulation(const mpu::MpuSurface& s, TriangleMesh& mesh, RestrictedDelaunayStats& stats);

}  // namespace mpumesh
