// Thin wedges of a region trimmed from the labelled triangulation of a complex (docs/
// method.md "One restricted Delaunay triangulation"). Where a region tapers to an edge
// between two others, as a thin layer of soft tissue does where it runs out between bone
// and air, its two boundary facets at that edge meet at a small angle inside it, its
// wedge; every tetrahedron there has a dihedral angle no larger. A region's cells around
// such an edge (one run of them, their dihedral angles there adding up to less than the
// least wedge) go to the neighbouring region beside them that fills more of the turn
// around the edge, one edge's run at a time, and only where every region's boundary stays
// a closed manifold (at every edge of the changed cells each region's cells make at most
// one run; at every vertex of theirs each of the two regions' cells, and the rest, are
// each connected); the edges of the changed cells are looked at again, round by round,
// so a taper is cut back to where it is thick enough. The background is never trimmed.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "multi/labelled_delaunay.h"
#include "multi/region_wedges.h"

namespace mpumesh::multi {

struct WedgeTrimStats {
  int64_t cells = 0;  // cells given to another region
  int rounds = 0;     // rounds that changed cells
};

// The rounds the trimming makes at most (the least wedge: multi/region_wedges.h).
inline constexpr int kWedgeTrimRounds = 30;

// `pts` holds the vertices' points by their info.
WedgeTrimStats trim_thin_wedges(labelled::Dt& dt, const std::vector<Eigen::Vector3d>& pts,
                                double min_wedge_deg = kMinWedgeDeg, int max_rounds = kWedgeTrimRounds);

}  // namespace mpumesh::multi
