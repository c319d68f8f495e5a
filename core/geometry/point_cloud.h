// An oriented point cloud in physical millimetres: the input of the MPU fit.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace mpumesh {

struct PointCloud {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;  // unit, outward
  // Per point, how far the point may lie from the surface relative to the fit's tolerance
  // (mpu::FitOptions::eps): a fit's error at the point counts divided by it. Empty: 1 for
  // every point. Points of a label map have one that follows their normal
  // (mpu/fit_tolerance.h).
  std::vector<float> tolerance;
  size_t size() const { return positions.size(); }
};

}  // namespace mpumesh
