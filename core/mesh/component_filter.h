// Keeping the wanted structures of a closed mesh, as "keep largest island" and a minimum
// size do in Slicer and InVesalius: the scanner's table or head rest, a loose fragment.
// A component is a connected set of triangles; its enclosed volume is the signed volume
// of its triangles (positive for an outward-facing shell, negative for the wall of a
// cavity). A cavity belongs to the shell that encloses it (the nearest one, by a ray's
// crossings) and is kept or dropped with it; shells are ranked by their own volume.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

struct ComponentOptions {
  int64_t largest = 0;        // keep the N shells of largest volume (0: all)
  double min_volume_mm3 = 0;  // and drop the shells enclosing less than this
  // And drop the shells whose mean thickness, 2 × volume / area (a plate's thickness), is
  // below this: a sheet folded onto itself, two sides of one surface that enclose nothing.
  double min_thickness_mm = 0;
  bool active() const { return largest > 0 || min_volume_mm3 > 0 || min_thickness_mm > 0; }
};

struct DroppedComponent {
  int64_t triangles = 0, vertices = 0;
  double volume_mm3 = 0;  // the shell's, less its cavities'
  double area_mm2 = 0;    // the shell's and its cavities'
  bool thin = false;      // dropped for its thickness alone
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // of its vertices
};

struct FilteredMesh {
  TriangleMesh mesh;  // the kept triangles, their vertices (in order) and attributes
  int64_t kept = 0;   // shells kept
  std::vector<DroppedComponent> dropped;  // largest first
};

FilteredMesh filter_components(const TriangleMesh& mesh, const ComponentOptions& filter);

// A closed mesh's parts: each shell with the cavities it encloses, as a mesh of its own
// (its vertices in their order, without attributes), largest enclosed volume first.
struct MeshPart {
  TriangleMesh mesh;
  double volume_mm3 = 0;  // the shell's, less its cavities'
  double area_mm2 = 0;    // the shell's and its cavities'
};
std::vector<MeshPart> split_parts(const TriangleMesh& mesh);
// How many parts split_parts finds.
int64_t count_parts(const TriangleMesh& mesh);

// Throws InputError naming `path` when the filter kept nothing (only --min-volume can drop
// every structure); says how much the largest encloses.
void require_kept(const FilteredMesh& f, const ComponentOptions& filter, const std::string& path);

}  // namespace mpumesh
