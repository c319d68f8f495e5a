// The original MPU method's mesh (Ohtake et al. 2003), the paper's second baseline: f
// sampled on a uniform grid over the fitted points' bounding box (plus two cells), and
// marching cubes on -f (inside >= 0) on the given backend. The mesh is closed and
// oriented outward wherever the zero set stays inside the grid.
#pragma once

#include "compute/compute_backend.h"
#include "geometry/triangle_mesh.h"
#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

struct PolygonizeStats {
  std::array<int64_t, 3> dims{0, 0, 0};  // grid points
  double cell = 0;                       // mm
  double eval_seconds = 0, mc_seconds = 0;
};

// cell <= 0: the default, 1/200 of the data box's largest side. Throws InputError when
// the grid would exceed 2^30 points or f has no zero crossing on it.
TriangleMesh polygonize(const MpuSurface& s, double cell, ComputeBackend& backend, PolygonizeStats* stats = nullptr);

}  // namespace mpumesh::mpu
