// A written multi-material complex (a mesh whose faces carry label_a < label_b) against a
// material phantom's analytic truth: each interface's distance to its true surface and
// its normals' error, the junction curves' distance to the true ones (both ways: ours to
// the truth, and the truth's points to ours), and each label's volume against the
// analytic one. Nothing here comes from the product's fit.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "phantom/material_phantom.h"

namespace mpumesh::phantom {

struct InterfaceTruth {
  int64_t a = 0, b = 0, triangles = 0;
  bool true_interface = false;  // the phantom has an interface (a, b)
  double distance_mean = 0, distance_p99 = 0;        // mm, area-weighted samples
  double normal_mean_deg = 0, normal_p95_deg = 0;    // faces, area-weighted
  // The same over the faces farther than `rim` from every junction curve and sharp rim
  // (MaterialPhantom::rim_distance).
  double normal_mean_away_deg = 0, normal_p95_away_deg = 0;
};

struct LabelTruth {
  int64_t label = 0;
  double volume_error = 0;  // (enclosed - analytic) / analytic
};

struct ComplexTruth {
  std::vector<InterfaceTruth> interfaces;
  std::vector<LabelTruth> labels;
  double distance_mean = 0, distance_p99 = 0, normal_mean_deg = 0, normal_p95_deg = 0;  // all interfaces
  double normal_mean_away_deg = 0, normal_p95_away_deg = 0;                            // away from rims
  double junction_p95 = 0, junction_max = 0;       // our junction edges' points to the true curves
  double junction_cover_p95 = 0;                   // the true curves' points to our junction edges
  int64_t junction_edges = 0;
  double worst_volume_error = 0;                   // the largest |volume_error|
  int64_t foreign_triangles = 0;  // tagged with a pair the phantom has no interface for
};

// `rim`: the distance from a junction curve or sharp rim within which faces are left out
// of the "away" normals (mm).
ComplexTruth complex_truth(const MaterialPhantom& m, const TriangleMesh& complex, double rim);

}  // namespace mpumesh::phantom
