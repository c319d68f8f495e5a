// Specks of a multi-material complex: closed pieces of a label's region smaller than a
// label map resolves (a fraction of a voxel), as a single surface's run drops its
// specks. In a label map they are where a label one voxel thin thins out between two
// others (soft tissue between bone and air): the piece is a lens whose two faces meet
// at its rim at a few degrees or less, and no tetrahedron inside it can be better shaped
// than that angle. Such a piece goes to the region it shares the most area with: its
// triangles against that region are removed, those against its other neighbour are
// relabelled (and turned, where the pair's order changes), as if its cells had carried
// that region's label all along, so every label's boundary stays closed.
#pragma once

#include <cstdint>

#include "geometry/triangle_mesh.h"

namespace mpumesh::multi {

struct SpeckStats {
  int64_t merged = 0;      // pieces merged into a neighbour
  double volume_mm3 = 0;   // their enclosed volume, together
};

// Each closed piece of a label's boundary (oriented out of it) enclosing a positive
// volume under `min_volume_mm3` and touching at most two other regions is merged into
// the one it shares the most area with (the lower label on a tie), in rounds until none
// is left (a piece next to another piece merged in the same round waits for the next).
// Vertices no triangle uses any more are dropped. A piece touching three or more regions
// is kept: merging it could leave a region twice around one edge.
SpeckStats merge_specks(TriangleMesh& complex, double min_volume_mm3);

}  // namespace mpumesh::multi
