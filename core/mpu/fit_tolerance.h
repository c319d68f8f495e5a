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

#include <Eigen/Dense>
#include <cstdint>
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

// Label maps. A crisp label has no partial volume: its contour points are quantised to
// the grid, the boundary anywhere within half a step of where the contour puts it along
// each axis, the pixel in-plane and the slice along the slice axis. Their spread about
// the surface reaches √2 steps peak to peak where the normal runs diagonally, so the fit
// holds a point to kLabelSteps grid steps measured along its normal n:
//   ε(n) = 1.5 √(pixel² (1 - (n·a)²) + slice² (n·a)²),   a the slice axis,
// but no more than half the distance to the nearest point facing the other way (the
// other face of a plate or gap thinner than that), and no less than ε0. Each point's
// PointCloud::tolerance is ε(n) / ε0: the fit counts its error there divided by it and
// weighs it by its inverse square (local_fit.cpp).
inline constexpr double kLabelSteps = 1.5;

// A label map's fit reaches across its slices: its automatic smallest radius is at least
// kLabelMinRadiusSlices slice spacings (FitOptions::min_radius_floor), so that every ball
// holds the contours of the slices on either side of its centre. The fit's curvature varies
// with the grid's steps at that scale, so the curvature a label map's mesh carries is the
// fit's averaged at that scale (mesh/surface_attributes.h smooth_curvature).
inline constexpr double kLabelMinRadiusSlices = 1.5;

struct LabelGrid {
  Eigen::Vector3d slice_axis{0, 0, 1};  // unit
  double pixel = 0, slice = 0;          // mm
};

struct LabelTolerance {
  double median_factor = 1;  // of ε(n) / ε0
  int64_t thin_points = 0;   // held below ε(n) by a face facing the other way
};

// `index`: a tree over cloud.positions; `eps`: ε0 (mm).
LabelTolerance set_label_map_tolerance(PointCloud& cloud, const KdTree& index, const LabelGrid& grid, double eps);

}  // namespace mpumesh::mpu
