// Consistent outward orientation of a manifold triangle mesh's components.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

// Orients the triangles of each edge-connected component consistently (breadth-first
// through shared edges; the mesh must be manifold) and then each component so that its
// normals agree with `outward` (one direction per vertex) by an area-weighted vote.
// Returns the number of components flipped.
int64_t orient_components(TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& outward);

}  // namespace mpumesh
