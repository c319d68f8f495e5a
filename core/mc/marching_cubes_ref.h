// The CPU reference of the marching-cubes kernels (shaders/marching_cubes_classify.comp and
// shaders/marching_cubes_generate.comp), in double precision, with the same output order as the GPU:
// vertices by owning grid point (x fastest), then edge axis x, y, z; triangles by cube,
// then table order. Vertex positions are continuous grid indices of the padded field.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mc/mc_field.h"

namespace mpumesh::mc {

// A crossing never sits closer than this fraction of an edge to a grid point, so that
// voxels exactly at the threshold give no zero-length edges. The shader uses the same.
inline constexpr double kMinEdgeFraction = 0.01;

struct McMesh {
  std::vector<std::array<double, 3>> grid_vertices;  // #V by 3, padded-grid index units
  std::vector<std::array<uint32_t, 3>> triangles;    // #F by 3
};

McMesh marching_cubes_ref(const McField& field);

}  // namespace mpumesh::mc
