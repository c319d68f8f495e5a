// The marching-cubes baseline (the paper's voxel-level mesh, `mpumesh mc`): threshold the
// volume, pad it, run the kernel on the given backend and map the vertices to mm. The
// result is a closed, oriented 2-manifold with outward normals.
#pragma once

#include "compute/compute_backend.h"
#include "mc/mc_field.h"
#include "geometry/triangle_mesh.h"

namespace mpumesh {

// Maps padded-grid coordinates to mm and orients triangles outward (a direction matrix
// with negative determinant mirrors the grid, so the triangles are flipped).
TriangleMesh grid_mesh_to_physical(const mc::McMesh& m, const Volume& vol);

// Throws InputError naming the volume when the threshold selects no voxel or every voxel
// (no surface).
TriangleMesh marching_cubes(const Volume& vol, mc::ThresholdRange range, ComputeBackend& backend);

}  // namespace mpumesh
