// A written mesh against a phantom's analytic surface: how far its vertices lie from the
// surface, how far its faces' normals turn from the true ones, how well its curvature
// follows the true Gaussian curvature, and how its spacing follows the true |K|. Nothing
// here comes from the product's fit: the truth is the shape's closed form; the mesh's
// curvature is the K its PLY carries when it has one, else the mesh's own discrete K
// (angle deficit over a third of the incident area).
#pragma once

#include <string>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "phantom/ct_phantom.h"
#include "volume/volume.h"

namespace mpumesh::phantom {

struct TruthFigures {
  int64_t vertices = 0, triangles = 0;
  double distance_mean = 0, distance_p99 = 0;     // mm, over vertices
  double normal_mean_deg = 0, normal_p95_deg = 0;  // faces, area-weighted
  bool curvature_from_file = false;                // the PLY's K (else discrete)
  double gauss_rank = 0;                           // Spearman of the mesh's K with the true K
  double gauss_median_error = 0;                   // median |K - K_true| / max |K_true|
  double spacing_high_low = 0;                     // median spacing, highest tenth of |K| / lowest tenth
  double spacing_rank = 0;                         // Spearman of spacing with the true |K|
  // Capsule only: the parts' median K (1/mm²) and spacing (mm).
  double cap_gauss = 0, barrel_gauss = 0, cap_spacing = 0, barrel_spacing = 0;
  double volume_error = 0;  // (enclosed volume - the shape's) / the shape's
  // With the scan's grid: the slice-phase modulation of |H| (mesh/slice_phase.h).
  double slice_modulation = 0;
};

// The value below which a fraction q of the weight w lies.
double weighted_quantile(const std::vector<double>& x, const std::vector<double>& w, double q);

// `scan`, when given, is the volume the mesh was made from (its slices' geometry).
TruthFigures truth_figures(const TriangleMesh& mesh, const Shape& shape, const Volume* scan = nullptr);

}  // namespace mpumesh::phantom
