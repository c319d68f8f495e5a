// Exact Euclidean distance transform of a 2D binary image (Felzenszwalb and Huttenlocher
// 2012: two passes of the 1D lower envelope of parabolas), with anisotropic pixel sizes.
#pragma once

#include <cstdint>
#include <vector>

namespace mpumesh::seg {

// Squared distance from the centre of each pixel to the centre of the nearest pixel whose
// mask value equals `target`, with pixel sizes wx, wy; +infinity when there is none.
std::vector<float> squared_distance_2d(const uint8_t* mask, int64_t nx, int64_t ny, uint8_t target, double wx = 1.0,
                                       double wy = 1.0);
// The same into `out` (resized), for loops over many slices.
void squared_distance_2d(const uint8_t* mask, int64_t nx, int64_t ny, uint8_t target, double wx, double wy,
                         std::vector<float>& out);

}  // namespace mpumesh::seg
