// Mesh optimisation after the triangulation (the paper's "further work"): the restricted
// Delaunay mesh of the particles, made better shaped while its vertices stay on f = 0.
// Each round
// 1. flips every edge that is not locally Delaunay (its two opposite angles add up to
//    more than π) where the two triangles are nearly coplanar (their normals within
//    max_flip_dihedral_deg) and the new edge's midpoint lies no farther from the surface
//    than the old one's, or than flip_offset of the edge's length; in the last
//    smooth_flip_rounds rounds, step 5's flips follow;
// 2. collapses the shortest edge of each triangle whose smallest angle is under
//    min_keep_deg, the poorest first, where the mesh stays a manifold (the edge's ends
//    share only its two opposite vertices, and each of those keeps three neighbours) and
//    the merged vertex, at the edge's midpoint on f = 0 or at either end, turns no
//    triangle by more than max_turn_deg and raises the smallest angle around it (a
//    vertex of three or four triangles, or an edge much shorter than its neighbours',
//    leaves a smallest angle near 20° that moves alone cannot raise);
// 3. moves every vertex to the density-weighted centroid of its triangles' centroids (a
//    centroidal Voronoi tessellation's step, Du, Faber and Gunzburger 1999, restricted to
//    the surface; density 1 / s² for a target spacing s: the vertices a unit of area
//    holds at that spacing. The particles already put the vertices at their sizes; a
//    step evens the shapes and keeps the sizes. At 1 / s⁴, whose centroidal cells have
//    size s, each step pulls the vertices up the size gradient and skews the triangles
//    there), within the tangent plane, then back onto f = 0 by Newton steps on the
//    compute backend (ComputeBackend::particle_project, as the particles are). A move is
//    kept when no triangle around the vertex turns by more than max_turn_deg and the
//    smallest angle around it does not fall (or stays at least min_keep_deg).
// 4. After the rounds, a vertex of three triangles whose tetrahedron with its three
//    neighbours has a dihedral angle under flat_cap_deg is removed (the triangle of its
//    neighbours takes its three, where its smallest angle is no worse): such a vertex sits
//    within a fraction of an edge of that triangle, on a flat patch or at the tip of a
//    knife-edge rim, and that tetrahedron is the one a volume mesh must have there. Then
//    the vertices of triangles still under polish_below_deg move, one by one, to the
//    place near them on f = 0 that most raises the smallest angle around them (a search
//    in the tangent plane, a few passes), turning no triangle by more than max_turn_deg:
//    the rounds' centroids even the shapes on the whole but leave a few triangles near
//    20° where the surface folds sharply (the rim of a thin plate).
// 5. Flips for smoothness (a data-dependent triangulation, Dyn, Levin and Rippa 1990):
//    an edge between triangles more than smooth_flip_above_deg apart is flipped when the
//    sum of the dihedral angles at it and at the four edges around it falls by more than
//    smooth_flip_gain_deg, neither new triangle has an angle under min_keep_deg, the two
//    triangles lose no more than smooth_flip_shape_per_deg of radius ratio per degree
//    gained, none of the five edges folds more sharply than the sharpest did (a fold
//    near 180° holds a flat tetrahedron in a volume mesh), and the new edge lies as near
//    the surface as in step 1. The largest gains go first, one flip per patch of six
//    triangles a pass; a flip whose triangles then cross another is undone (exact
//    predicates). Delaunay flips alone choose the diagonal of a quad by its angles,
//    whichever way the surface bends across it; where it bends one way (a ridge, a
//    saddle, a plate's rim) the other diagonal can follow it. The relaxation after it
//    evens the shapes again.
// Triangles that then cross others (exact predicates, mesh/cgal_geometry.h) have their
// vertices frozen and the rounds are done again; after three tries, the mesh is kept as
// it was.
// The mesh stays a closed oriented manifold: flips keep the link condition (the new edge
// is no edge yet), collapses keep it too, and moves change no connectivity. The vertices
// collapsed away are dropped at the end (the others keep their order).
#pragma once

#include <cstdint>
#include <vector>

#include "common/progress_fn.h"
#include "compute/compute_backend.h"
#include "geometry/triangle_mesh.h"
#include "mpu/mpu_surface.h"

namespace mpumesh {

struct OptimizeOptions {
  int rounds = 4;                     // 0: no optimisation
  double max_flip_dihedral_deg = 30;  // the two triangles of a flipped edge
  double flip_offset = 0.05;          // of the edge's length
  double max_turn_deg = 30;           // a moved vertex's triangles
  double min_keep_deg = 30;           // a move may lower a smallest angle that stays above this;
                                      // a triangle under it has its shortest edge collapsed
  double flat_cap_deg = 15;           // step 4's vertices of three triangles
  double polish_below_deg = 25;       // step 4's triangles
  int polish_passes = 4;              // 0: no step 4
  int smooth_flip_rounds = 3;         // the last rounds that do step 5 (0: none)
  double smooth_flip_above_deg = 10;  // step 5's edges: their dihedral angle at least this
  double smooth_flip_gain_deg = 1;    // step 5: the five edges' dihedral sum falls by more
  double smooth_flip_shape_per_deg = 0.01;  // step 5: radius ratio the pair may lose per degree gained
  int newton_steps = 3;
};

// The smallest angle, the share of triangles under 30° and the mean radius ratio.
struct ShapeFigures {
  double min_angle_deg = 0, pct_below_30 = 0, radius_ratio = 0;
};
ShapeFigures shape_figures(const TriangleMesh& m);

struct OptimizeStats {
  int rounds = 0;
  int64_t flips = 0, moves = 0;   // over all rounds (a vertex moved in two rounds counts twice)
  int64_t collapses = 0;          // edges collapsed and flat vertices removed, each a vertex and two triangles fewer
  int64_t polish_moves = 0;       // step 4's
  int64_t smooth_flips = 0;       // step 5's
  int retries = 0;                // rounds done again with frozen vertices (three: none kept)
  int64_t frozen = 0;             // vertices frozen for that
  ShapeFigures before, after;
  double seconds = 0;
};

// `spacing`: each vertex's target spacing (mm). Throws nothing for a valid closed mesh; a
// vertex whose projection fails (∇f vanishes) keeps its place. `progress` is told the
// rounds done over the rounds (again from 0 when the rounds are done again), 1 at the end.
OptimizeStats optimize_mesh(TriangleMesh& mesh, const mpu::MpuSurface& s, ComputeBackend& backend,
                            const std::vector<double>& spacing, const OptimizeOptions& opt = {},
                            const ProgressFn& progress = {});

}  // namespace mpumesh
