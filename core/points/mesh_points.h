// Oriented points from a surface mesh, for remeshing (`mpumesh run MESH`): every vertex
// with its area-weighted normal and, with `centroids`, every triangle's centroid with its
// face normal, so that the MPU fit sees the faces and not only the corners (a coarse
// exact mesh). Degenerate triangles add nothing; vertices of no (non-degenerate) triangle
// are left out.
#pragma once

#include "geometry/triangle_mesh.h"
#include "geometry/point_cloud.h"

namespace mpumesh::pts {

PointCloud mesh_points(const TriangleMesh& mesh, bool centroids = true);

}  // namespace mpumesh::pts
