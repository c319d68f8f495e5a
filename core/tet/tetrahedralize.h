// Linear tetrahedra that fill a closed, oriented surface mesh, with the surface's
// triangles as their boundary: TetGen 1.5 (Si 2015, "TetGen, a Delaunay-based quality
// tetrahedral mesh generator"; Debian's libtet1.5-dev) tetrahedralizes the surface as a
// piecewise linear complex without splitting its triangles (-Y), refines the inside by
// Delaunay refinement to a radius-edge ratio and a smallest dihedral angle (-q), with
// the size each point asks for (-m), and improves the tetrahedra by flips, smoothing and
// point insertion (-O), aiming at no dihedral angle above max_dihedral (-o/). The steps:
// 1. a coarse quality tetrahedralization of the surface (radius-edge ratio 2);
// 2. the size at its nodes: the surface's own spacing at the boundary, growing by
//    `grading` mm per mm of distance from it, up to `size`:
//        s(x) = min(size, min_b (s_b + grading |x - b|)),
//    s_b the mean length of the edges at the surface vertex b;
// 3. that mesh refined (-r) to the quality and the sizes, interpolated between its nodes;
//    where a tetrahedron with a dihedral angle under 10° has its four nodes on the surface
//    (flat under a fold of it, or across a plate; no flip or inner node mends it), a point
//    beneath it or inside the plate, and the refinement done again from step 2's mesh
//    with those points (-i);
// 4. regions: the tetrahedra joined across faces that are not the surface's; a region
//    whose surface triangles face into it lies in a cavity (the inside of a closed inner
//    wall) and is removed;
// 5. the inner nodes of slivers moved to raise their stars' smallest dihedral angle
//    (perturb_slivers in tetrahedralize.cpp);
// 6. a sliver left (its nodes on the surface, or none of them free to move far enough):
//    it and its neighbours of one region, grown where the new tetrahedra are still poor,
//    refilled by a new node joined to their outer faces, where that raises the smallest
//    angle (tet/sliver_cavities.h).
// What none of these mends is a dihedral angle the surface itself makes: two of its
// triangles meeting at an edge at less than 10° inside (a knife-edge rim, a speck meshed
// by four vertices) bound a tetrahedron with that angle, whatever the points inside; only
// a point on the surface would mend it, and -Y forbids those. The pipeline removes the
// flat vertices of three triangles and the specks before (mesh/mesh_optimize.h,
// RunOptions::speck_voxels).
#pragma once

#include <cstdint>
#include <string>

#include "common/error.h"
#include "common/progress_fn.h"
#include "geometry/tet_mesh.h"
#include "geometry/triangle_mesh.h"
#include "tet/tet_quality.h"

namespace mpumesh {

struct TetOptions {
  double size = 0;           // largest edge length inside (mm); 0: four times the surface's median edge
  double grading = 0.3;      // growth of the size per mm from the surface
  double radius_edge = 1.3;  // TetGen -q: largest circumradius / shortest edge
  double min_dihedral = 15;  // TetGen -q: smallest dihedral angle it refines for (degrees)
  int optimize_level = 7;    // TetGen -O (0-9)
  // TetGen -o/: the largest dihedral angle its optimisation accepts (degrees). A sliver has
  // one near 180°; TetGen's own 165° keeps dozens of tetrahedra under 10° on the sample
  // CT's default mesh, 140° keeps those of the surface alone (step 5's note).
  double max_dihedral = 140;
  // A multi-material complex's (multi/complex_tetrahedralize.h): the background meshed too,
  // inside a box around the complex.
  bool background = false;
};

// One label's tetrahedra in a complex's volume mesh.
struct LabelTetFigures {
  int32_t label = 0;
  TetQuality quality;
  double boundary_volume = 0;               // enclosed by the label's boundary in the complex (mm³)
  double min_dihedral_at_interfaces = 180;  // of its tetrahedra with a node on the complex (degrees)
  double min_dihedral_at_junctions = 180;   // with a node on a junction curve (degrees)
};

struct TetStats {
  int64_t surface_points = 0;      // the input surface's vertices, all of them nodes
  int64_t boundary_points = 0;     // points TetGen added on the surface (0: -Y)
  int64_t interior_points = 0;     // nodes inside
  int64_t cavities_removed = 0;    // regions inside closed inner walls
  int64_t flat_tet_points = 0;     // points put inside to replace flat tetrahedra of surface nodes (step 3)
  int64_t perturbed = 0;           // inner nodes moved off slivers (step 5)
  int64_t sliver_cavities = 0;     // slivers' cavities refilled by a new node (step 6)
  double size = 0;                 // the size used (mm)
  double surface_volume = 0;       // enclosed by the input surface (mm³); a complex's: by its labels' boundaries
  double seconds = 0;
  TetQuality quality;
  std::vector<LabelTetFigures> labels;  // a complex's, ascending
  // The tetrahedra's volume against the surface's, in percent.
  double volume_difference_pct() const { return 100 * (quality.volume_mm3 - surface_volume) / surface_volume; }
};

// Throws InputError when the surface is not a closed, oriented manifold (with its border
// edges counted), or TetGen refuses it (the message names the problem it found).
TetMesh tetrahedralize(const TriangleMesh& surface, const TetOptions& opt, TetStats* stats = nullptr,
                       const ProgressFn& progress = {});

// `e`, an error of the volume mesh ("tetmesh: ..."), as one about the run of `input`
// ("INPUT: volume mesh: ...").
InputError volume_mesh_error(const std::string& input, const InputError& e);

// Throws InputError naming the option (`volume_size`, `volume_grading`).
void validate(const TetOptions& o);

}  // namespace mpumesh
