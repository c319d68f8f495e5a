// An oriented point cloud in physical millimetres: the input of the MPU fit.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace mpumesh {

struct PointCloud {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;  // unit, outward
  size_t size() const { return positions.size(); }
};

}  // namespace mpumesh
