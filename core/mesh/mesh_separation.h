// Keeping one closed mesh out of others: a label of a label map meshed after its
// neighbours yields to them where its surface crosses theirs (seg/label_map.h keeps touching
// labels half a voxel apart, which independent fits of one interface can still cross on
// curved faces).
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

// Whether the two meshes' axis-aligned bounding boxes meet (no crossing is possible
// otherwise).
bool bounding_boxes_overlap(const TriangleMesh& a, const TriangleMesh& b);

struct SeparationStats {
  int64_t crossings_before = 0, crossings_after = 0;  // triangle pairs, over every fixed mesh
  std::vector<int64_t> crossings_with;  // after, per mesh of `fixed` (0 where the boxes do not meet)
  int64_t moved_vertices = 0;
  int64_t reverted_vertices = 0;  // moves undone because they folded or crossed `a` itself
  int rounds = 0;
  double max_move_mm = 0;
};

// Moves vertices of `a` until it crosses none of the meshes in `fixed` (closed, oriented),
// round by round up to `max_rounds`, checking with exact predicates:
// - a vertex of `a` inside a fixed mesh goes to its closest point there and `margin` (mm)
//   beyond it;
// - the other vertices of a crossing triangle go inward along their own normal, past the
//   deepest vertex of the fixed mesh that pokes through the triangle's plane, and
//   `margin` more.
// A move that flips one of its triangles or makes `a` cross itself is undone. The moved
// vertices keep their attributes (normals, curvature of their surface nearby).
SeparationStats separate_from(TriangleMesh& a, const std::vector<const TriangleMesh*>& fixed, double margin,
                              int max_rounds = 4);

}  // namespace mpumesh
