// Connected components of a binary 3D mask (6-connected, the inside connectivity that the
// marching-cubes table and the contours use: ambiguous faces separate inside corners).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace mpumesh::seg {

struct ComponentStats {
  int64_t count = 0;
  std::vector<int64_t> sizes;  // voxels per component, largest first
};

ComponentStats mask_components(const std::vector<uint8_t>& mask, std::array<int64_t, 3> dims);

}  // namespace mpumesh::seg
