// Stage 7: the restricted Delaunay triangulation of the particles on the MPU surface
// (docs/method.md "Triangulation"): the Delaunay facets of the particles (CGAL's
// Delaunay_triangulation_3) whose dual Voronoi edge crosses f = 0, i.e. whose two Voronoi
// vertices (circumcentres) have f of opposite signs. Where the sample is too thin for a
// manifold (an edge with more than two such facets, a vertex with more than one fan), a
// point is added where the Voronoi edge of the largest facet there crosses f = 0
// (bisection), as CGAL's surface mesher does with its Manifold_tag, and the cells it
// changes are looked at again, round by round. Where a particle ends on no facet because
// a plate thinner than the sampling lies whole in its Voronoi cell, a point on the plate's
// other side is added and the manifold repair runs again (lost sheets, twice at most).
// A facet far wider than the sampling around it gets its crossing as a point too (the
// sheet under it is sampled by none). A component that no particle holds is removed
// (mesh/spurious_components.h). The triangles are oriented consistently through their
// shared edges, each component outward by ∇f (mesh/orientation.h); then edge collapses
// and flips remove most thin triangles (mesh/triangulation_cleanup.h). The manifold
// repair is in mesh/manifold_repair.cpp, the lost sheets in mesh/lost_sheets.cpp.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "common/progress_fn.h"
#include "geometry/triangle_mesh.h"
#include "mpu/mpu_surface.h"

namespace mpumesh {

class ComputeBackend;

struct RestrictedDelaunayStats {
  int64_t particles = 0;       // points given
  int64_t repair_points = 0;   // points added for a manifold (and used by the mesh)
  int64_t repair_rounds = 0;   // rounds of the manifold repair
  int64_t wide_facets = 0;     // facets far wider than the sampling around them (an
                               // unsampled sheet under them) given their crossing as a point
  int64_t unused_points = 0;   // given points on no restricted facet (dropped)
  int64_t repair_merged = 0;   // repair crossings left out: within 5% of their ball's radius
                               // of one inserted just before them (the same missing point)
  int64_t sheet_points = 0;    // repair points put on the far side of a thin plate that a
                               // particle's Voronoi cell held whole (lost sheets)
  int64_t spurious_components = 0;  // made of repair points only (no particle or sheet
  int64_t spurious_triangles = 0;   // point), removed: on a sheet no particle reached
  int64_t flipped_components = 0;
  int64_t edge_flips = 0, edge_collapses = 0;  // thin triangles removed (mesh/thin_triangles.h)
  int64_t vertices_relaxed = 0;                 // moved to mend the thin triangles left
  int64_t cleanup_retries = 0;  // times the cleanup was redone to undo a self-intersection
  double seconds = 0;
  // Of which: Delaunay triangulation of the particles, f at the circumcentres (all rounds),
  // the manifold repair's crossings and insertions, the facets in order and oriented, the
  // thin-triangle cleanup with its self-intersection check.
  double seconds_delaunay = 0, seconds_evaluate = 0, seconds_repair = 0, seconds_mesh = 0, seconds_cleanup = 0;
};

// The mesh's vertices are the used particles (in their given order), then the repair
// points (less those that edge collapses merged away). The repair stops with a
// NumericalError after max_repair_points (0: the larger of 20,000 and the particle count)
// or 100 rounds. f at the Voronoi vertices is computed on `backend` (on the CPU when
// null); the rest runs on the CPU. The same points on the same backend give the same mesh.
// `progress` is told the phases done: the Delaunay triangulation (0.5), the repair (up to
// 0.8, by the share of the first round's elements repaired), the mesh and its clean-up (1).
TriangleMesh restricted_delaunay(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points,
                                 RestrictedDelaunayStats* stats = nullptr, int64_t max_repair_points = 0,
                                 ComputeBackend* backend = nullptr, const ProgressFn& progress = {});

}  // namespace mpumesh
