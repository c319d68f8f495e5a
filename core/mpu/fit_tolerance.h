// The fit's tolerance ε0 (FitOptions::eps) for points that come from a volume. The
// contour points of a segmented scan scatter about the true surface by the image noise
// and the segmentation's sub-voxel error; a fit held below that scatter interpolates it,
// and the curvature that drives the particles becomes the curvature of the noise. So
// the tolerance follows the data:
//   ε0 = max(pixel, 3 σ)
// with `pixel` the in-plane voxel size (the finest detail a slice resolves) and σ the
// points' scatter estimated from the points themselves (points/point_noise.h). Points
// given as a cloud or a mesh keep the sub-spacing default of fit_mpu (a quarter of their
// median spacing), since nothing says they are noisy.
#pragma once

#include <string>

#include "common/kd_tree.h"
#include "geometry/point_cloud.h"

namespace mpumesh::mpu {

struct Tolerance {
  double eps = 0;    // mm
  double noise = 0;  // σ, mm
  double pixel = 0;  // mm
  std::string source;  // the rule and the figure that decided it, for the reports
};

// `pixel`: the in-plane voxel size (Volume::in_plane_spacing); `index`: a PointIndex's
// tree over the points, if the caller has one.
Tolerance volume_tolerance(const PointCloud& cloud, double pixel, const KdTree* index = nullptr);

}  // namespace mpumesh::mpu
