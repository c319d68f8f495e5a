// Data contract of the marching-cubes kernels (marching_cubes_classify.comp, marching_cubes_generate.comp) and
// their CPU reference (core/mc/marching_cubes_ref.cpp). One invocation per grid point of
// the padded field; a point owns the grid edges that leave it along +x, +y, +z and, when
// it is not on a far face, the cube whose min corner it is.
#ifndef MPUMESH_MC_ABI_H
#define MPUMESH_MC_ABI_H
#include "shared/abi_prelude.h"

#define MC_BIND_FIELD 0   // float[points]: >= 0 inside
#define MC_BIND_INFO 1    // uint[points]: bits 0-2 crossing owned edges, bits 3-10 cube case
#define MC_BIND_VOFF 2    // uint[points]: vertex count, then (scanned) first vertex index
#define MC_BIND_TOFF 3    // uint[points]: triangle count, then (scanned) first triangle index
#define MC_BIND_VERTS 4   // vec4[vertices]: padded-grid index coordinates
#define MC_BIND_TRIS 5    // uint[3 * triangles]
#define MC_BIND_TABLE 6   // uniform McTable

// Case c: edges of its triangles as nibbles (8 per word, x then y then z), w = count.
#define MC_TABLE_CASES 256

ABI_BEGIN
struct McPush {
  uint nx, ny, nz;
  uint count;       // nx * ny * nz
  uint row;         // invocations per dispatch row (2D dispatch of large grids)
  float min_frac;   // crossings kept this far from grid points (fraction of an edge)
  uint pad0, pad1;
};
ABI_END

#ifdef __cplusplus
static_assert(sizeof(mpumesh::abi::McPush) == 32, "McPush must match the GLSL push block");
#endif
#endif
