// An indexed triangle mesh in millimetres: #V by 3 vertices, #F by 3 vertex indices,
// counter-clockwise seen from outside (normals point out of the enclosed volume).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

namespace mpumesh {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
};

}  // namespace mpumesh
