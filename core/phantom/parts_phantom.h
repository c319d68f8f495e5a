// A surface mesh of several closed parts, as a segmentation's export of touching bones
// gives one, for remeshing a mesh part by part: five closed parts, each a surface of
// revolution with edges about `edge` mm long, tilted against the axes:
//   1, 2  a ball of radius 10 cut by a plane 2.5 mm above its centre into its larger part
//         and its cap, each closed by the same disc (the same vertices and triangles in
//         both): two parts that touch;
//   3     a ball of radius 5, `gap` mm from part 1;
//   4     a spheroid (radii 4, 4, 7), `gap` mm from part 1 on the other side;
//   5     a ball of radius 3, 3 mm from part 1.
// The parts are numbered as the complex numbers them, by enclosed volume, largest first.
#pragma once

#include <Eigen/Dense>
#include <utility>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh::phantom {

// One part's smooth surface, the truth its mesh is a chordal approximation of: the
// spheroid (rho / a)^2 + (z / c)^2 = 1 in its frame, or (side -1, +1) the part of the
// ball of radius a below or above z = cut together with the disc that closes it.
struct TruePart {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // local to world
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double a = 1, c = 1;
  int side = 0;
  double cut = 0;
  // The distance from p (world) to this surface.
  double distance(const Eigen::Vector3d& p) const;
};

struct PartsPhantom {
  TriangleMesh mesh;  // the parts one after another, each with its own vertices
  std::vector<double> part_volumes;  // of the meshes as built (mm³), part 1 first
  std::vector<TruePart> truth;       // part 1 first
  std::vector<std::pair<int, int>> touching;  // the parts that share a face: (1, 2)
  double gap = 0;  // the narrowest distance between parts that do not touch (mm)
  // The distance from p to the nearest part's smooth surface.
  double true_distance(const Eigen::Vector3d& p) const;
  // The distance of a mesh's surface to the parts' smooth surfaces (mm): three points inside
  // each triangle (barycentric 2/3, 1/6, 1/6 and rotations), each weighted by a third of
  // its area.
  struct Distances {
    double mean = 0, p99 = 0;
  };
  Distances distance_to_truth(const TriangleMesh& m) const;
};

PartsPhantom parts_phantom(double edge = 1.0, double gap = 0.2);

}  // namespace mpumesh::phantom
