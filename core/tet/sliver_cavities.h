// Step 6 of a volume mesh (tet/tetrahedralize.h): the slivers that no inner node mends.
// A tetrahedron whose four nodes lie on the surface (flat under a fold of it, across a
// plate, or between two regions' interfaces) has no node step 5 may move, and TetGen's
// refinement with the points of step 3 can leave or make some. Such a tetrahedron and its
// neighbours form a cavity whose faces are kept as they are; one new node inside, joined
// to every face, refills it (Bowyer-Watson's cavity filling, with the node placed for the
// shape rather than on a circumcentre).
#pragma once

#include <cstdint>

#include "geometry/tet_mesh.h"

namespace mpumesh {

// For each tetrahedron whose smallest dihedral angle is under `below_deg`: a cavity of it
// and its neighbours of its own region (never across a face between regions or on the
// boundary), refilled by a new node joined to the cavity's faces. The node goes where the
// new tetrahedra's smallest dihedral angle is largest (a pattern search from the cavity's
// centroids that climbs into the cavity's kernel first); the cavity then grows across the
// faces whose tetrahedron with the node is still under `below_deg` or not positive, and
// the node is placed again (eight cavities at most; where the faces stop being one closed
// surface, by a whole ring). The best cavity whose refill beats its own smallest angle,
// with positive tetrahedra that fill exactly its volume and keep every node, is refilled;
// the first to reach `below_deg` ends the search. The boundary triangles, the regions'
// volumes and every node already there stay as they are. Returns the nodes added.
int64_t refill_sliver_cavities(TetMesh& m, double below_deg);

}  // namespace mpumesh
