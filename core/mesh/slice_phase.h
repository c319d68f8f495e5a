// Slice terraces, measured on a mesh: a surface that follows a stack of slices has a ridge
// or a band of curvature at every slice. The mean curvature |H| at the vertices (the
// mesh's own discrete H: the cotangent Laplacian over the mixed Voronoi area,
// mesh/surface_attributes.h), averaged in `bins` bins of each vertex's phase within the
// slice period along the slice axis (phase 0 at the slices' centres); the modulation is
// (largest bin - smallest) / the mean over all vertices. A smooth surface shows a small
// modulation, the noise of a bin's mean; a staircase a large one.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "volume/volume.h"

namespace mpumesh {

struct SlicePhase {
  std::vector<double> bin_mean_abs_h;  // 1/mm
  std::vector<int64_t> bin_vertices;
  double mean_abs_h = 0;
  double modulation = 0;
};

// `origin` lies on a slice's centre plane, `slice_axis` (unit) is the slices' normal and
// `slice_spacing` (mm) their period.
SlicePhase slice_phase(const TriangleMesh& mesh, const Eigen::Vector3d& origin, const Eigen::Vector3d& slice_axis,
                       double slice_spacing, int bins = 8);
// The slices of `scan`: through its origin, along its third axis, at its slice spacing.
SlicePhase slice_phase(const TriangleMesh& mesh, const Volume& scan, int bins = 8);

}  // namespace mpumesh
