// The marching-cubes case table, generated (not copied) so that it is topologically
// consistent: every ambiguous face separates the inside corners (the inside is
// 6-connected, the outside 26-connected). Because a face's segments depend on that face's
// four corners only, neighbouring cubes agree on every shared face, and the surface of a
// padded volume is a closed, oriented 2-manifold. The classic Lorensen table, built by
// complementary symmetry, is not: it leaves holes at ambiguous faces.
//
// Corner c of a cube sits at (c&1 ^ (c>>1&1), c>>1&1, c>>2&1) in the usual order
// 0:(0,0,0) 1:(1,0,0) 2:(1,1,0) 3:(0,1,0) 4:(0,0,1) 5:(1,0,1) 6:(1,1,1) 7:(0,1,1);
// edges 0-3 ring the bottom face, 4-7 the top, 8-11 are vertical. Case index bit c is set
// when corner c is inside. Triangles are counter-clockwise seen from outside.
#pragma once

#include <array>
#include <cstdint>

namespace mpumesh::mc {

inline constexpr int kMaxTrianglesPerCube = 8;

struct CubeCase {
  int triangle_count = 0;
  std::array<int8_t, 3 * kMaxTrianglesPerCube> edges{};  // cube edge ids, 3 per triangle
};

inline constexpr std::array<std::array<int, 3>, 8> kCorner = {{
    {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
inline constexpr std::array<std::array<int, 2>, 12> kEdgeCorners = {{
    {0, 1}, {1, 2}, {3, 2}, {0, 3}, {4, 5}, {5, 6}, {7, 6}, {4, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};

// Which grid point owns a cube edge (offset from the cube's min corner) and along which
// axis the edge runs: every grid edge belongs to the point at its lower end.
struct EdgeOwner {
  int dx, dy, dz, axis;
};
inline constexpr std::array<EdgeOwner, 12> kEdgeOwner = {{
    {0, 0, 0, 0}, {1, 0, 0, 1}, {0, 1, 0, 0}, {0, 0, 0, 1},
    {0, 0, 1, 0}, {1, 0, 1, 1}, {0, 1, 1, 0}, {0, 0, 1, 1},
    {0, 0, 0, 2}, {1, 0, 0, 2}, {1, 1, 0, 2}, {0, 1, 0, 2}}};

// The 256 cases, built once on first use.
const std::array<CubeCase, 256>& case_table();

}  // namespace mpumesh::mc
