// The remeshing benchmark's peer: what a user picks to remesh a surface with CGAL,
// CGAL::Polygon_mesh_processing::isotropic_remeshing on a Surface_mesh, three iterations
// (one tangential relaxation step each), at a target edge length chosen for a triangle
// count: L = sqrt(4 A / (sqrt(3) N)), the edge of N equilateral triangles covering the
// area A, then corrected once by the count the first try gave (only the second try is
// timed).
#pragma once

#include <cstdint>

#include "geometry/triangle_mesh.h"

namespace mpumesh::bench {

struct RemeshResult {
  TriangleMesh mesh;
  double edge_length = 0;  // the target of the timed run (mm)
  double seconds = 0;      // the timed run: building the Surface_mesh, remeshing, back
};

RemeshResult cgal_isotropic_remesh(const TriangleMesh& input, int64_t triangles, int iterations = 3);

}  // namespace mpumesh::bench
