// What a multi-material complex is, measured from its triangles: each label's region
// (enclosed volume, closedness), each interface (area, triangle shape), the junction
// curves (edges where three or more regions' boundaries meet), and the triangle pairs
// that cross.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh::multi {

struct RegionFigures {
  int64_t label = 0;
  int64_t triangles = 0;
  double volume_mm3 = 0;   // enclosed by its boundary, oriented out of it
  int64_t defects = 0;     // edges of its boundary not closed and oriented (0: closed manifold)
  int64_t components = 0;  // connected pieces of its boundary
  // Vertices where its boundary is not one disc (two fans or more: the region pinched to a
  // point there, as where a layer thinner than the sample's spacing has its two faces
  // touch); 0 with no defects: a closed oriented 2-manifold.
  int64_t pinched_vertices = 0;
  // At the junction edges, the angle inside the region between its two boundary
  // triangles (its wedge; degrees): a tetrahedron of the region on that edge has a
  // dihedral angle no larger. The smallest, and how many are under 10 degrees.
  double min_wedge_deg = 360;
  int64_t wedges_under_10 = 0;
};

struct InterfaceFigures {
  int64_t label_a = 0, label_b = 0;
  int64_t triangles = 0;
  double area_mm2 = 0;
  double min_angle_deg = 0, mean_radius_ratio = 0;
};

struct ComplexFigures {
  std::vector<RegionFigures> regions;  // the labels, ascending (not the background)
  std::vector<InterfaceFigures> interfaces;  // by (a, b)
  int64_t junction_edges = 0, junction_curves = 0;  // curves: connected runs of junction edges
  double junction_length_mm = 0;
  double min_angle_deg = 0;            // over all triangles
  double min_angle_off_junction_deg = 0;  // over triangles with no vertex on a junction edge
  double mean_radius_ratio = 0;
  int64_t crossing_pairs = 0;  // triangle pairs sharing no vertex that intersect
};

// A complex is a mesh whose face_labels tag every triangle with the labels (a < b) of the
// regions it separates, oriented from a into b (a PLY with label_a, label_b).

// The labels present in the tags, ascending, 0 included.
std::vector<int64_t> complex_labels(const TriangleMesh& complex);

// Label l's boundary, oriented out of it: its triangles of the complex, those where l is
// the second label flipped; over the complex's vertices.
TriangleMesh label_boundary(const TriangleMesh& complex, int64_t label);

// Edges of label l's boundary with other than two triangles, or whose two triangles run
// the same way along them (not a closed oriented manifold there).
int64_t boundary_defects(const TriangleMesh& complex, int64_t label);

// The junction edges (vertex pairs): edges whose triangles separate three or more
// regions between them.
std::vector<std::array<uint32_t, 2>> junction_edges(const TriangleMesh& complex);

ComplexFigures measure_complex(const TriangleMesh& complex, bool crossings = true);

}  // namespace mpumesh::multi
