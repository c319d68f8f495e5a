// The figures of the HTML report (mpumesh run --html, mpumesh report) that come from a
// mesh rather than from the run that made it: the region its zoomed panels show, and how
// its vertex spacing follows the curvature.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh::report {

// The paper's Fig. 4 region: the cell (of size `radius`) of the mesh with the largest
// integrated |K| among cells holding at least 30 vertices of the outer surface (the
// farthest third from the centre, facing away from it: inner structures are hidden from
// any view), looked at along its mean normal. The mesh must carry normals and curvature.
struct ViewRegion {
  Eigen::Vector3d centre, view;
  double radius;
};
ViewRegion pick_region(const TriangleMesh& m);

// Each vertex's spacing (the mean length of its edges) against |K| at the mesh's scale
// (gauss_at_mesh_scale), over the vertices with edges, and their rank correlation.
struct VertexAdaptivity {
  std::vector<double> abs_gauss, spacing;
  double rank_correlation = 0;
};
VertexAdaptivity vertex_adaptivity(const TriangleMesh& m);

}  // namespace mpumesh::report
