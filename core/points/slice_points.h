// Stage 3: a segmentation to an oriented point cloud (docs/method.md, "Contours, points
// and normals").
// - Contour points: the vertices of every slice's sub-pixel contours (marching squares on
//   the segmentation's boundary field), at the slice's z.
// - Cap points: where a region ends between two slices k and k+1, a point over every pixel
//   that is inside in one slice and lies at least one slice spacing (in-plane) from the
//   region of the other: there the surface is within 45° of the slice plane and the
//   contours of the two slices are too far apart to close it. Steeper walls are covered by
//   the contours of both slices. Spacing: the pixel grid, like the contour points. Height:
//   between the slices, rising from the first slice's contour toward the other slice's
//   region in proportion to the in-plane distances to both (a ruled surface between the
//   contours); where the other slice has no region at all (a dome top), rising at 45° from
//   the contour up to the mid-plane, the best guess for an apex somewhere between the two
//   slices. Flat mid-plane caps would give normals up to 45° off along every cap's rim.
//   With partial_volume_caps, the height comes from the grey of the two slabs instead
//   where the column allows it (see partial_volume_rise in slice_points.cpp).
//   The padding slices are empty, so a structure cut by the first or last slice gets a cap
//   (at most half a slice outside it).
// - Normals: PCA over the points within a radius that reaches the adjacent slices (one
//   slice's neighbours are collinear), counting only neighbours whose orientation
//   reference agrees, so the two faces of a thin wall do not mix. Oriented outward by the
//   reference: the contour's in-plane outward direction plus ±z where the adjacent slices
//   say the surface faces up or down; ±z for caps. Where the neighbourhood is degenerate
//   (too few points, or nearly collinear) the reference itself is the normal.
#pragma once

#include <cstdint>

#include "geometry/point_cloud.h"
#include "segment/segmentation.h"
#include "volume/volume.h"

namespace mpumesh::pts {

struct PointOptions {
  bool caps = true;
  // Cap heights from the grey of the two slabs the surface crosses (partial volume) where
  // the column allows it, else from the contours alone (a ruled surface). On the capsule
  // phantom the cap points lie 0.076 mm from the true caps, against 0.363 mm ruled.
  bool partial_volume_caps = true;
  // Where the field, linear between the two slices, crosses zero below the mid-plane, a
  // cap rises no further than that crossing: a quarter slice toward another label in a
  // label map's indicator (seg/label_map.h), where toward the background the crossing is
  // the mid-plane and the ruled height stays. Set for label maps only: an intensity's
  // linear crossing is no height.
  bool caps_to_field_crossing = false;
  // Cap heights where the in-plane signed distance to the slices' contours, a parabola in
  // z through three slices, crosses zero (slice_points.cpp, curved_rise), not a chord
  // between two: for label maps, which have no partial volume.
  bool curved_caps = false;
  // PCA radius: max(radius_slices * slice spacing, radius_pixels * in-plane spacing).
  double radius_slices = 1.5;
  double radius_pixels = 3.0;
  // A neighbourhood is degenerate below this many points, or when its middle eigenvalue
  // is below collinear_ratio times the largest.
  int min_neighbours = 6;
  double collinear_ratio = 0.02;
};

struct PointStats {
  int64_t contours = 0;
  int64_t contour_points = 0;
  int64_t cap_points = 0;
  int64_t degenerate_normals = 0;  // given the orientation reference instead of PCA
  double pca_radius_mm = 0;
  double contour_seconds = 0, cap_seconds = 0, normal_seconds = 0;
};

struct SlicePoints {
  PointCloud cloud;               // physical mm
  std::vector<uint8_t> is_cap;    // per point
  std::vector<int32_t> slice;     // contour points: slice index; caps: k of the k/k+1 mid-plane
  PointStats stats;
};

// `geometry` gives spacing, origin and direction (the segmented volume).
SlicePoints extract_points(const seg::Segmentation& s, const Volume& geometry, const PointOptions& opt = {});

}  // namespace mpumesh::pts
