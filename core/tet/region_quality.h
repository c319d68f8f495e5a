// A volume mesh's quality region by region: each region's tetrahedra measured on their own
// (tet/tet_quality.h), for a multi-material mesh's labels.
#pragma once

#include <cstdint>
#include <map>

#include "geometry/tet_mesh.h"
#include "tet/tet_quality.h"

namespace mpumesh {

// By region, ascending; each TetQuality's `nodes` is the whole mesh's count.
std::map<int32_t, TetQuality> quality_by_region(const TetMesh& m);

}  // namespace mpumesh
