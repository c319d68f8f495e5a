// Stage 4: fits the MPU surface to an oriented point cloud (docs/method.md, "The MPU surface").
// An octree over the points' bounding cube (enlarged by `margin`); a cell of centre c and
// diagonal d gets the support radius R = alpha d, grown by lambda R until the ball holds
// nmin points; its fit is a height field when every normal in the ball lies within 90° of
// the weighted mean normal and the cell is near the points, else a general quadric with
// auxiliary points; a cell whose Taubin error exceeds eps is split into 8, down to
// max_depth, unless its ball had to grow (its children would only grow back to the same
// points) or is held at min_radius (its children's balls would be as large); a cell whose
// children's balls would be held at min_radius splits only above 2 eps. Cells are fitted in
// parallel, one octree level at a time, and kept in a fixed order: the result does not
// depend on the thread count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/kd_tree.h"
#include "mpu/mpu_surface.h"
#include "geometry/point_cloud.h"

namespace mpumesh::mpu {

enum class LocalFit { kOrthopoly, kQuadric };

struct FitOptions {
  LocalFit local_fit = LocalFit::kOrthopoly;
  double eps = 0;         // mm; 0 = 0.25 x the median nearest-neighbour spacing of the points
  int nmin = 30;
  double alpha = 0.75;
  double lambda = 0.1;
  int max_depth = 10;
  // Smallest support radius (mm); negative = 1.5 x the median distance to the 12th
  // nearest point, about the largest sampling gap (between slices for a CT stack), so that
  // no ball fits one slice's collinear contour alone.
  double min_radius = -1;
  // The automatic smallest radius is at least this (mm): for a label map 1.5 slice
  // spacings, so that every ball reaches the slices on either side of its centre (on the
  // sample project's bone mask taken at 3 mm slices, the 12th-neighbour rule gives 4.1 mm,
  // and the surface bends at every slice: the slice-phase modulation of |H| is 0.54; 0.24
  // at 4.5 mm).
  double min_radius_floor = 0;
  int max_degree = 4;     // orthopoly degree cap
  // The orthopoly height fields fit the points' normals too, as slopes (local_fit.h), with
  // the slope length a quarter of the median distance to the 12th nearest point. For
  // points whose normals are exact or nearly (analytic, a smooth mesh's) it makes K
  // truer between a slice stack's contours; for normals by PCA of the contours (a scan's)
  // it gains nothing and makes the fit a third slower, so it is off by default.
  bool fit_normals = false;
  double margin = 0.05;   // of the bounding box's largest side, on every side
  int grid_cells = 0;     // lookup grid cells per side; 0 = from the median leaf radius
};

void validate(const FitOptions& o);

struct FitStats {
  int64_t leaves = 0, height_orthopoly = 0, height_quadric = 0, general_quadric = 0, two_sheets = 0;
  int64_t over_eps = 0;         // leaves still above eps
  // Leaves above eps kept because their children's balls would be held at the smallest
  // radius and their error is within the larger bound that applies there.
  int64_t kept_below_held_bound = 0;
  std::array<int64_t, 5> degree_counts{};  // orthopoly leaves by degree (index = degree)
  int max_depth_reached = 0;
  int64_t duplicates_removed = 0;  // input points at exactly the position of an earlier one
  double eps = 0, min_radius = 0, seconds = 0;
  // The distinct points' median distance to their 12th nearest (median_spacing), when the
  // smallest radius or the slope length came from it; else 0.
  double gap12 = 0;
  // Of which: duplicates, k-d tree and spacing; each octree level (index = depth); the
  // lookup grid.
  double seconds_setup = 0, seconds_grid = 0;
  std::vector<double> seconds_by_depth;
};

// `index`: a PointIndex's tree over cloud.positions, when the caller has one; searched
// when no point is a duplicate (else the fit builds its own over the distinct points).
MpuSurface fit_mpu(const PointCloud& cloud, const FitOptions& opt, FitStats* stats = nullptr,
                   const KdTree* index = nullptr);

const char* local_fit_name(LocalFit f);

}  // namespace mpumesh::mpu
