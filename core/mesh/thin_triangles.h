// Cleanup of the restricted Delaunay mesh's few thin triangles, which sit next to the
// triangulation's repair points (a repair point close to a particle makes a needle):
// - collapse: the shortest edge uv of a triangle under `below_deg` whose other edges are
//   at least three times longer merges u into v (u the later vertex: a repair point before
//   a particle), when the link condition holds (u and v share exactly the two opposite
//   vertices, so the mesh stays manifold) and no triangle around u turns by more than
//   max_dihedral_deg;
// - flip: an edge ab shared by abc and bad becomes cd when that raises the smaller of the
//   two triangles' minimum angles, cd is no edge yet, the quad is nearly flat (normals
//   within max_dihedral_deg) and the new edge's midpoint lies no farther from the surface
//   (`surface_distance`) than the old edge's, or than max_offset_mm.
// Orientation is kept; vertices left unused are removed. No triangle with a `frozen`
// vertex changes.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "mesh/edge_edit.h"

namespace mpumesh {

struct ThinTriangleOptions {
  double below_deg = 20;
  double max_dihedral_deg = 20;
  double max_offset_mm = 0.05;
  int max_passes = 10;
  FrozenVertices frozen;  // per input vertex
};

struct ThinTriangleStats {
  int64_t flips = 0, collapses = 0;
  std::vector<uint32_t> kept;  // input index of each output vertex
};

ThinTriangleStats remove_thin_triangles(TriangleMesh& mesh,
                                        const std::function<double(const Eigen::Vector3d&)>& surface_distance,
                                        const ThinTriangleOptions& opt = {});

// What collapses and flips cannot mend (a needle between two repair points 70 µm apart
// whose ends share a third neighbour, so that the collapse would pinch the surface):
// each vertex of a triangle under `below_deg` moves toward the mean of its neighbours (all
// the way, half, a quarter), back onto the surface by `project`, when that raises the
// smallest angle around it and turns none of its triangles by more than max_turn_deg.
// Round by round, up to `rounds`. Returns the vertices moved (each once). No vertex with
// `frozen` set moves.
struct RelaxOptions {
  double below_deg = 20;
  double max_turn_deg = 30;
  int rounds = 20;
  FrozenVertices frozen;  // per vertex
};
std::vector<uint32_t> relax_thin_triangles(TriangleMesh& mesh,
                                           const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& project,
                                           const RelaxOptions& opt = {});

}  // namespace mpumesh
