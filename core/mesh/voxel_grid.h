// Whether a surface mesh is the marching-cubes surface of a scan: its vertices lie on the
// edges of a regular voxel grid (two of each vertex's coordinates on the grid's planes,
// the third interpolated along the edge), as marching cubes puts them. Such a mesh
// carries the scan's staircase and noise, so remeshing it fits it with the tolerance a
// volume gets (mpu/fit_tolerance.h) rather than as exact data.
#pragma once

#include <cstddef>
#include <optional>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

// The grid's spacing along x, y and z (mm) when at least kGridVertexShare of the vertices
// lie on its edges; nothing otherwise (a grid in a rotated frame is not found). Along
// each axis, the planes are v0 + i s: v0 the coordinate most vertices share, s the
// smallest gap between the kGridTopValues most shared coordinates (those that at least
// three vertices, and a tenth as many as share v0, share), divided by the
// smallest k (1-4) that puts kGridAxisShare of the vertices' coordinates on planes.
inline constexpr double kGridVertexShare = 0.9;
inline constexpr double kGridAxisShare = 0.1;
inline constexpr size_t kGridTopValues = 20;
std::optional<Eigen::Vector3d> voxel_grid_spacing(const TriangleMesh& mesh);

}  // namespace mpumesh
