// Multi-material label-map phantoms with analytic truth: several labels that touch, as a
// segmentation gives them (every voxel holds the label at its centre, no partial volume),
// tilted against the slices. Each knows the label at any point, the true interface between
// any two regions (the background, 0, counts as a region), the junction curves where
// three regions meet, and every label's volume. The suite:
//   split ball  a ball cut by a plane through its centre into labels 1 and 2: interfaces
//               (0,1), (0,2) (hemispheres) and (1,2) (a disc); one junction circle;
//   nested      a ball (1) inside a spherical shell (2): interfaces (1,2), (0,2);
//   sectors     a cylinder cut into three 120° sectors (1, 2, 3) about its axis:
//               junctions along the axis (1,2,3), along the three seams on the barrel
//               and the six radii on the end faces (0,i,j);
//   joint       a ball (1) in a hemispherical cup (2) with a gap of one slice spacing
//               between them: (0,1) and (0,2), no (1,2).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "volume/volume.h"

namespace mpumesh::phantom {

struct MaterialPhantom {
  enum Kind { kSplitBall, kNested, kSectors, kJoint } kind = kSplitBall;
  std::string name;
  // Split ball, nested (outer), joint (ball), sectors (cylinder): the radius R (mm).
  double radius = 15;
  // Nested: the inner ball's radius. Joint: the gap. Sectors: the half-length.
  double inner = 8;
  double thickness = 4;  // joint: the cup's wall
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // local to world
  Eigen::Vector3d centre{0, 0, 0};
  Eigen::Vector3d spacing{0.7, 0.7, 1.6};  // the label map's pixel and slice
  double margin_mm = 5;

  // The label at p (0 the background).
  int label_at(const Eigen::Vector3d& p) const;
  // The labels present, ascending, without 0.
  std::vector<int> labels() const;
  // The analytic volume of a label (mm³).
  double label_volume(int label) const;
  // Whether regions a < b share an interface.
  bool shares_interface(int a, int b) const;
  // The distance from p to the true interface between regions a < b (infinity where they
  // share none), with the closest point and the interface's unit normal there, pointing
  // from a into b.
  double interface_distance(int a, int b, const Eigen::Vector3d& p, Eigen::Vector3d* normal = nullptr,
                            Eigen::Vector3d* closest = nullptr) const;
  // The distance from p to the nearest junction curve (infinity where there is none).
  double junction_distance(const Eigen::Vector3d& p) const;
  // The distance from p to the nearest junction curve or sharp rim of one interface (the
  // sectors' end-face circles, the cup's rim): where the true normal jumps.
  double rim_distance(const Eigen::Vector3d& p) const;
  // Points along every junction curve, at most `step` mm apart.
  std::vector<Eigen::Vector3d> junction_points(double step) const;
  // The largest distance of a labelled point from the centre (for the grid).
  double extent() const;
};

// The label map: every voxel holds the label at its centre.
Volume material_scan(const MaterialPhantom& m);

// The suite, 30-40 mm across, tilted, 0.6-0.7 mm pixels and slices 2-3 times thicker.
std::vector<MaterialPhantom> material_suite();

}  // namespace mpumesh::phantom
