// Combinatorial checks of a triangle mesh: border edges, edges with more than two faces,
// vertices whose triangles form more than one fan, orientation, connected components,
// Euler characteristic and genus.
#pragma once

#include <cstdint>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

struct Topology {
  int64_t vertices = 0;   // referenced by at least one triangle
  int64_t edges = 0;
  int64_t triangles = 0;
  int64_t border_edges = 0;         // one face
  int64_t nonmanifold_edges = 0;    // three or more faces
  int64_t nonmanifold_vertices = 0; // triangles around it form more than one fan
  int64_t misoriented_edges = 0;    // two faces that traverse it in the same direction
  int64_t degenerate_triangles = 0; // repeated vertex index
  int64_t components = 0;           // connected through shared vertices
  int64_t euler = 0;                // V - E + F
  bool closed = false;              // no border edges
  bool manifold = false;            // every edge two faces, every vertex one fan
  bool oriented = false;            // manifold and consistently oriented
  // Total genus, sum over components, meaningful for closed orientable manifolds:
  // (2 * components - euler) / 2. -1 when the mesh is not a closed manifold.
  int64_t genus = -1;
};

Topology analyze_topology(const TriangleMesh& mesh);

// Throws InputError unless `mesh` is a closed manifold: "PATH: NOUN is not a closed
// manifold (B border edges, N non-manifold edges); WHY".
void require_closed_manifold(const TriangleMesh& mesh, const std::string& path, const std::string& noun,
                             const std::string& why);

// Connected component id of every triangle (0-based, in order of first triangle).
std::vector<int32_t> triangle_components(const TriangleMesh& mesh, int64_t* count);

}  // namespace mpumesh
