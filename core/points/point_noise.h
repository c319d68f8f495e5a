// The noise of a point cloud, estimated from the points: at up to 4,000 evenly picked
// points, a quadratic height field over the PCA plane of the 32 nearest points, and the
// RMS of their residuals (corrected for the 6 fitted parameters); the median over the
// picked points. The quadric takes the shape's own bending out, so on clean points of a
// smooth surface the estimate is the fit's own error at that scale (a small fraction of
// the spacing), and on contour points of a noisy segmentation it is their scatter about
// the surface: the noise a fit must not follow.
#pragma once

#include "common/kd_tree.h"
#include "geometry/point_cloud.h"

namespace mpumesh::pts {

// `index`: a PointIndex's tree over cloud.positions, when the caller has one (else one is
// built).
double estimate_noise(const PointCloud& cloud, const KdTree* index = nullptr);

}  // namespace mpumesh::pts
