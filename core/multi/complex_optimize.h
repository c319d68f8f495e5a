// The complex's triangles made better shaped, each vertex kept on its interface and the
// junction curves held (docs/method.md "Several labels"). The restricted Delaunay facets
// of the complex are as the particles and the repair points left them; where a repair
// point lies near a particle, or thin plates put particles close together, slivers stay.
// Each round
// 1. flips every edge inside one interface (its two triangles, and only they, tagged with
//    the same pair) that is not locally Delaunay (its two opposite angles add up to more
//    than pi), where the two triangles are nearly coplanar (normals within 30°), the new
//    edge is no edge yet, and the smaller of the pair's smallest angles rises;
// 2. moves every vertex inside one interface (all its triangles tagged with one pair a, b)
//    toward the area-weighted centroid of its triangles' centroids, within its tangent
//    plane, then back onto f_a = f_b (MaterialField::project_interface), where a and b
//    stay its two most inside regions; the move is kept when no triangle around it turns
//    by more than 30° and the smallest angle around it rises. The candidate places are
//    computed in parallel from the round's positions, the moves decided in vertex order,
//    so the result does not depend on the threads.
// Neither a flip nor a move takes a region's wedge at an edge (its angle between its two
// triangles there, which bounds its tetrahedra's dihedral angles; multi/thin_wedges.h)
// under 10°, or lower where it is under 10° already.
// Vertices on a junction curve (triangles of two or more pairs) never move, and no edge
// of a junction is flipped, so every label's boundary stays the closed oriented manifold
// it was, with the same junctions. Where changed triangles then intersect others that
// they did not (exact predicates, mesh/cgal_geometry.h; triangles that share a vertex
// included: a fold there stops TetGen), their vertices are frozen and the rounds start
// again from the complex as it was; after three tries, the complex is kept as it was.
#pragma once

#include <cstdint>

#include "geometry/triangle_mesh.h"
#include "multi/material_field.h"

namespace mpumesh::multi {

struct ComplexOptimizeStats {
  int rounds = 0;
  int64_t flips = 0, moves = 0;
  double min_angle_before_deg = 0, min_angle_after_deg = 0;
  bool reverted = false;  // changed triangles still intersected others: the complex as it was
  double seconds = 0;
};

// The rounds a run makes.
inline constexpr int kComplexOptimizeRounds = 3;

// `complex`'s face_labels are the field's labels (MaterialField::label).
void optimize_complex(const MaterialField& field, TriangleMesh& complex, int rounds = kComplexOptimizeRounds,
                      ComplexOptimizeStats* stats = nullptr);

}  // namespace mpumesh::multi
