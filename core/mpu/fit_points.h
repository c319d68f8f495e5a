// The points a fit starts from: without exact duplicates, and spanning a volume.
#pragma once

#include <cstdint>

#include "geometry/point_cloud.h"

namespace mpumesh::mpu {

// The cloud without exact duplicates (the first of each position kept, the others in
// their order): a repeated point would make the median spacing, hence eps and the
// smallest radius, zero. *removed: how many were dropped.
PointCloud without_duplicates(const PointCloud& in, int64_t* removed);

// Throws InputError when the points span no volume: all on one plane (or line), where no
// closed surface can be fitted.
void check_not_flat(const PointCloud& c);

}  // namespace mpumesh::mpu
