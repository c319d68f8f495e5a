// The scalar field marching cubes runs on: the volume's voxels mapped to a signed value
// that is >= 0 inside the threshold range [lo, hi] and < 0 outside, padded by one voxel on
// every side so that every surface closes.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "volume/volume.h"

namespace mpumesh::mc {

struct ThresholdRange {
  double lo = 0;
  double hi = std::numeric_limits<double>::infinity();
};

struct McField {
  std::array<int64_t, 3> dims{0, 0, 0};  // padded: the volume's dims + 2
  std::vector<float> values;             // x fastest; >= 0 inside
  int64_t point_count() const { return dims[0] * dims[1] * dims[2]; }
};

// f = min(v - lo, hi - v). A padding voxel gets minus the value of its nearest interior
// voxel (at most -0.5), so that a structure cut by the volume border closes half a voxel
// outside it. NaN voxels count as outside. Throws InputError if lo > hi.
McField make_threshold_field(const Volume& vol, ThresholdRange range);

// Parses "LO" or "LO:HI" (HU or whatever unit the volume holds).
ThresholdRange parse_threshold(const std::string& text);

}  // namespace mpumesh::mc
