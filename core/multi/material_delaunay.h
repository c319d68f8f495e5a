// One restricted Delaunay triangulation of a multi-material complex's particles (docs/
// method.md "Several labels"): CGAL's Delaunay triangulation of all of them, each
// Voronoi vertex (a cell's circumcentre, computed robustly as for one surface) labelled
// by the field's region there, the infinite cells the background's. A facet is kept when
// its dual Voronoi edge joins two regions a < b; it is oriented from a into b and tagged
// with the pair, once. The facets bound unions of cells, so every region's boundary has
// an even number of facets at each edge; where it has more than two, or is pinched at a
// vertex (labelled_delaunay.h pinched_at; a sample too thin there, both), the crossing
// of the widest such facet's Voronoi edge with the labelling is
// added as a point (on the interface of the two regions it separates), round by round,
// as the one-surface triangulation does. Then each facet with an angle under 20 degrees
// gets the centre of its surface Delaunay ball, for a few rounds, each repaired again.
// Last, the regions' thin wedges are trimmed (multi/thin_wedges.h).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "multi/complex_sampling.h"
#include "multi/material_field.h"

namespace mpumesh::multi {

struct MaterialComplex {
  // Each triangle oriented from region pair[0] into pair[1]; mesh.face_labels holds the
  // two regions' labels (multi/complex_figures.h reads a complex from it).
  TriangleMesh mesh;
};

struct ComplexDelaunayStats {
  int64_t points = 0, cells = 0, facets = 0;
  int64_t repair_points = 0, repair_rounds = 0;
  int64_t refine_points = 0, refine_rounds = 0;  // points added for facets' angles
  int64_t trimmed_cells = 0, trim_rounds = 0;    // multi/thin_wedges.h
  int64_t bad_edges = 0;  // edges of a region's boundary with other than two facets, left
  int64_t pinches_found = 0, pinches = 0;  // (region, vertex) pairs where its boundary is
                                           // not one disc: at the first look, and left
  double seconds = 0;
};

// With `resolve_gaps`, a facet between two labels whose dual edge passes through a third
// region (two labels a gap apart that is thinner than the sample) gets the labelling's
// crossings from both ends too: a mesh's parts, whose gaps can be a fraction of an edge.
// A label map's gaps are a voxel or more, about the sample's spacing; on the sample
// project's masks the search leaves the repair unfinished with 100,000 points more,
// so a label map is triangulated without it.
MaterialComplex material_delaunay(const MaterialField& field, const std::vector<ComplexParticle>& particles,
                                  ComplexDelaunayStats* stats = nullptr, bool resolve_gaps = false);

}  // namespace mpumesh::multi
