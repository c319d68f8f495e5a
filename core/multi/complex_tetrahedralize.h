// One volume mesh of a multi-material complex (multi/complex_figures.h: every interface
// triangle once, tagged (a, b) and facing from a into b): TetGen on the complex as one
// piecewise linear complex, the interfaces its internal facets, every triangle kept as it
// is (-Y: no node is added on an interface, so the triangles the tetrahedra of two labels
// share are exactly the complex's), with the quality steps one closed surface has
// (tet/tetrahedralize.h: sizes graded from the complex's spacing, points for flat
// tetrahedra, slivers' inner nodes moved).
//
// Each tetrahedron's label: the tetrahedra joined across faces that are not the complex's
// form the regions; a region's label is the side of the complex's triangles it lies on
// (the triangle (a, b) faces out of a), by majority over its faces. This needs no point
// inside each label, which a thin or curved label (a shell, a plate) may not offer.
// Regions of the background (label 0) enclosed by labels are dropped, unless
// TetOptions::background asks for the background: then the complex is put in a box 10% of
// its largest extent (at least the inner size) larger on every side, the box's faces in
// triangles of the inner size, and the space between them is label 0.
#pragma once

#include "geometry/tet_mesh.h"
#include "geometry/triangle_mesh.h"
#include "tet/tetrahedralize.h"

namespace mpumesh::multi {

// Throws InputError (naming the label) when a label's boundary in the complex is not a
// closed oriented manifold, or TetGen refuses the complex.
TetMesh tetrahedralize_complex(const TriangleMesh& complex, const TetOptions& opt, TetStats* stats = nullptr,
                               const ProgressFn& progress = {});

// A closed, outward surface as a complex of one label, 1, against the background (its
// triangles turned to face from the background into it), for a volume mesh with its
// background.
TriangleMesh surface_as_complex(const TriangleMesh& surface);

// The volume mesh of any surface the product writes: a complex (face_labels) as a
// complex, a closed surface with TetOptions::background as a complex of one label in its
// box, else one closed surface (tetrahedralize).
TetMesh tetrahedralize_surface(const TriangleMesh& surface, const TetOptions& opt, TetStats* stats = nullptr,
                               const ProgressFn& progress = {});

}  // namespace mpumesh::multi
