// Mesh quality figures (mpumesh quality): topology, size, triangle shape (minimum angle,
// radius ratio 2*r_in/r_circ), smoothness (dihedral angle between neighbouring normals,
// area whose normal lies within 5 deg of a coordinate axis: voxel staircases) and, with a
// reference surface, distances in mm. Units: mm, mm^2, mm^3, degrees.
#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <optional>

#include "geometry/angle.h"
#include "mesh/topology.h"
#include "geometry/triangle_mesh.h"

namespace mpumesh {

struct DistanceStats {
  double mean = 0, p99 = 0, max = 0;  // mm, area-weighted samples of one surface to the other
};

struct Quality {
  Topology topo;
  int64_t self_intersections = -1;  // intersecting triangle pairs; -1 when not computed
  int64_t zero_area_triangles = 0;  // three distinct corners on one line (or one point)
  double area_mm2 = 0, volume_mm3 = 0;
  double edge_min = 0, edge_mean = 0, edge_max = 0;
  double angle_min = 0, angle_p01 = 0, angle_mean = 0;   // per-triangle minimum angle
  double pct_angle_below[3] = {0, 0, 0};                 // < 10, 20, 30 degrees
  double radius_ratio_mean = 0, pct_radius_ratio_below_half = 0;
  double dihedral_mean = 0, dihedral_p99 = 0;            // between neighbouring face normals
  double pct_area_axis_aligned = 0;                      // normal within 5 deg of an axis
  std::optional<DistanceStats> to_reference, from_reference;
  std::optional<double> hausdorff_mm, mean_distance_mm;  // symmetric
};

struct QualityOptions {
  bool self_intersections = true;
  const TriangleMesh* reference = nullptr;
};

Quality measure_quality(const TriangleMesh& mesh, const QualityOptions& opt = {});

// Each triangle's smallest angle (degrees) and radius ratio (as below), in order.
struct TriangleShapes {
  std::vector<double> min_angle_deg, radius_ratio;
};
TriangleShapes triangle_shapes(const TriangleMesh& mesh);
nlohmann::json quality_to_json(const Quality& q);
std::string quality_to_text(const Quality& q);

// Per triangle: minimum interior angle (degrees) and radius ratio 2*r_in/r_circ (1 for an
// equilateral triangle, 0 for a degenerate one).
double triangle_min_angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);
double triangle_radius_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);
// triangle_min_angle_deg(a, b, c) < deg, the same answer, with the arc tangents only for
// triangles whose largest cosine comes near cos(deg).
bool triangle_min_angle_below(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                              double deg);

}  // namespace mpumesh
