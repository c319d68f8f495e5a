// Sub-pixel contours of one slice: marching squares on a padded field (>= 0 inside,
// negative on the border ring, so every contour closes). One vertex per crossing pixel
// edge, placed by linear interpolation; an ambiguous (saddle) cell separates its inside
// corners, as the marching-cubes table does, so inside regions are 4-connected. Contours
// are closed polylines with the inside on their left: counter-clockwise around a region,
// clockwise around a hole (in index space, x right, y up).
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace mpumesh::pts {

struct Contour {
  std::vector<Eigen::Vector2d> points;  // pixel-index coordinates of the padded slice
  double signed_area() const;           // > 0 around a region, < 0 around a hole
};

std::vector<Contour> marching_squares(const float* field, int64_t nx, int64_t ny);

// Crossings closer than this fraction of an edge to a pixel centre are moved to it, so
// that no two contour vertices coincide (the same rule as marching cubes).
inline constexpr double kMinEdgeFraction = 0.01;

}  // namespace mpumesh::pts
