#include "mpu/fit_tolerance.h"

#include <fmt/format.h>

#include <algorithm>

#include "points/point_noise.h"

namespace mpumesh::mpu {

Tolerance volume_tolerance(const PointCloud& cloud, double pixel, const KdTree* index) {
  Tolerance t;
  t.pixel = pixel;
  t.noise = pts::estimate_noise(cloud, index);
  t.eps = std::max(t.pixel, 3 * t.noise);
  t.source = 3 * t.noise > t.pixel
                 ? fmt::format("3 x the contour points' scatter ({:.3f} mm), above the in-plane voxel ({:.3f} mm)",
                               t.noise, t.pixel)
                 : fmt::format("the in-plane voxel size ({:.3f} mm); the contour points' scatter is {:.3f} mm",
                               t.pixel, t.noise);
  return t;
}

}  // namespace mpumesh::mpu
