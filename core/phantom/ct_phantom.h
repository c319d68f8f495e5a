// CT-like phantoms with analytic truth, for the tests and mpumesh_bench_truth. A shape
// (ellipsoid, torus, capsule = cylinder with hemispherical caps, spherical shell) is
// placed by a rotation and a centre, so that it lies tilted against the slices. It knows
// the distance of a point to its surface and the outward normal and Gaussian curvature
// at the closest surface point. A scan of it is what a CT gives: every voxel the mean of
// the shape's indicator over the voxel's box (in-plane pixel and slice thickness,
// supersampled: partial volume), scaled to the contrast, plus Gaussian noise.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "volume/volume.h"

namespace mpumesh::phantom {

struct Shape {
  enum Kind { kEllipsoid, kTorus, kCapsule, kShell, kDisc } kind = kEllipsoid;
  // Ellipsoid: semi-axes a, b, c. Torus about local z: major radius a, minor b.
  // Capsule along local z: radius a, cylinder half-length b. Shell: outer radius a,
  // thickness b (two surfaces: the outer sphere and the inner one, normals out of the
  // material). Disc: the points within b of a flat disc of radius a in the local xy
  // plane (two flat faces joined by a half-torus rim: flat and curved parts).
  double a = 20, b = 20, c = 20;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // local to world
  Eigen::Vector3d centre{0, 0, 0};

  bool inside(const Eigen::Vector3d& p) const;
  // Unsigned distance to the surface; the outward normal and K at the closest point.
  double distance(const Eigen::Vector3d& p, Eigen::Vector3d* normal = nullptr, double* gauss = nullptr) const;
  // The closest point on the surface.
  Eigen::Vector3d closest_point(const Eigen::Vector3d& p) const;
  // Half the extent of the local bounding box (before rotation).
  Eigen::Vector3d half_extent() const;
  // The largest |K| on the surface (for errors relative to it).
  double max_abs_gauss() const;
  // The enclosed volume (mm³).
  double volume() const;
  // For the capsule: whether the closest surface point lies on a cap (else the barrel).
  bool on_cap(const Eigen::Vector3d& p) const;
};

// A rotation of `degrees` about `axis`, to place a shape tilted against the slices.
Eigen::Matrix3d tilt(double degrees, Eigen::Vector3d axis);

// An empty volume (0 everywhere) of voxels `spacing` over centre ± half, a fraction of a
// voxel off so that no symmetry plane of a shape centred there falls on the grid.
Volume phantom_grid(const Eigen::Vector3d& centre, const Eigen::Vector3d& half, const Eigen::Vector3d& spacing);

struct Scan {
  Eigen::Vector3d spacing{0.6, 0.6, 2.0};  // in-plane pixel and slice thickness, mm
  double inside_hu = 1000, outside_hu = 0, noise_hu = 50;
  uint32_t seed = 1;
  double margin_mm = 6;
  int sub_xy = 4, sub_z = 8;  // supersamples per voxel box
};

// The scanned volume (CT, HU) and the threshold halfway between the two levels.
Volume scan(const Shape& s, const Scan& c);
inline double half_level(const Scan& c) { return 0.5 * (c.inside_hu + c.outside_hu); }

struct Phantom {
  std::string name;
  Shape shape;
  Scan scan;
};

// The suite: an ellipsoid, a torus, a capsule and a 2.5 mm spherical shell, 40-70 mm
// across, tilted against the slices; in-plane pixels of 0.5-0.7 mm, slices 3-3.6 times
// thicker, noise of 40-60 HU at 1000 HU contrast.
std::vector<Phantom> suite();

// A label map of the shape, as a segmentation gives one: every voxel holds `label` where
// its centre lies inside the shape, else 0 (no partial volume, no noise).
Volume label_scan(const Shape& s, const Scan& c, int label = 1);

// The label-map suite: an ellipsoid, a torus and a disc (flat faces, a rounded rim), 40-60
// mm across, tilted against the slices; in-plane pixels of 0.6-0.7 mm, slices 2-3 times
// thicker.
std::vector<Phantom> label_suite();

}  // namespace mpumesh::phantom
