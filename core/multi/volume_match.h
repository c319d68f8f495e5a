// A label map's complex made to hold each label's volume. A crisp label's voxels give its
// volume without bias (each voxel the label at its centre), while the mesh of a smooth
// fit holds less wherever the surface is convex: the fit's rounding and the flat
// triangles' chords both cut inside it (a ball of 8 mm radius meshed at 1.3 mm edges
// loses about 0.6% to the chords alone). Each interface (a, b) is moved along its normal
// by s_ab = c_a - c_b, one constant c per region (the background's 0): the least
// movement, weighted by the interfaces' areas, that gives every label the volume of its
// voxels to first order,
//     sum_b A_ab (c_a - c_b) = V_a(voxels) - V_a(mesh)   for every label a,
// A_ab the area of interface (a, b). A vertex moves by the least-squares displacement d
// with n . d = s over its faces (area-weighted; along a junction curve, in the plane of
// the interfaces' normals), no longer than its faces' largest |s| nor a twentieth of its
// shortest edge. A vertex stays where its move would take a triangle's smallest angle
// under 30° lower, or a region's wedge at a junction edge under 15° lower (its
// tetrahedra are no better there: multi/thin_wedges.h), and where the moved triangles
// would cross others (exact predicates; the moves then start again, three tries, after
// which none is kept). Each s is held to `max_shift`, so that a label whose mesh lacks a
// part of its voxels (a piece thinner than the fit resolves, a speck merged into its
// neighbour) does not swell elsewhere to make up for it.
#pragma once

#include <cstdint>
#include <map>

#include "geometry/triangle_mesh.h"

namespace mpumesh::multi {

// The bound on an interface's move, in in-plane voxels.
inline constexpr double kVolumeShiftVoxels = 0.1;

struct VolumeMatchStats {
  // The largest |relative volume error| of a label against its voxels', before and after.
  double worst_before = 0, worst_after = 0;
  double largest_shift_mm = 0;  // the largest |s_ab| applied
  // Vertices held in place, for a triangle's angle or because moving them made triangles
  // cross; all of them when three tries crossed (reverted).
  int64_t frozen = 0;
  bool reverted = false;
};

// `volumes`: each label's voxel volume (mm³); labels of the complex not in it, and the
// background, keep their place (c = 0). Three rounds of the above.
VolumeMatchStats match_label_volumes(TriangleMesh& complex, const std::map<int64_t, double>& volumes,
                                     double max_shift);

}  // namespace mpumesh::multi
