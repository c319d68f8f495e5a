#include "mpu/fit_tolerance.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "points/point_noise.h"

namespace mpumesh::mpu {

Tolerance volume_tolerance(const PointCloud& cloud, double pixel, const KdTree* index) {
  Tolerance t;
  t.pixel = pixel;
  t.noise = pts::estimate_noise(cloud, index);
  t.eps = std::max(t.pixel, 3 * t.noise);
  t.source = 3 * t.noise > t.pixel
                 ? fmt::format("3 x the contour points' scatter ({:.3f} mm), above the in-plane voxel ({:.3f} mm)",
                               t.noise, t.pixel)
                 : fmt::format("the in-plane voxel size ({:.3f} mm); the contour points' scatter is {:.3f} mm",
                               t.pixel, t.noise);
  return t;
}

namespace {

// The nearest point whose normal turns away from p's by more than 120° (the other face
// of a plate or gap), for nanoflann's search: the squared distance bound shrinks with it.
class OppositeNearest {
 public:
  OppositeNearest(const PointCloud& cloud, const Eigen::Vector3d& normal, double radius)
      : cloud_(cloud), normal_(normal), best_(radius * radius) {}
  void init() {}
  size_t size() const { return 0; }
  bool full() const { return true; }
  bool addPoint(double d2, uint32_t j) {
    if (d2 < best_ && normal_.dot(cloud_.normals[j]) < -0.5) best_ = d2;
    return true;
  }
  double worstDist() const { return best_; }
  double distance() const { return std::sqrt(best_); }

 private:
  const PointCloud& cloud_;
  const Eigen::Vector3d& normal_;
  double best_;
};

}  // namespace

LabelTolerance set_label_map_tolerance(PointCloud& cloud, const KdTree& index, const LabelGrid& grid, double eps) {
  const double ratio = grid.slice / grid.pixel;
  const double widest = kLabelSteps * std::max(1.0, ratio) * grid.pixel;  // mm
  cloud.tolerance.assign(cloud.size(), 1.0f);
  std::vector<uint8_t> thin(cloud.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cloud.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3d& n = cloud.normals[i];
      const double c = n.dot(grid.slice_axis);
      const double step = kLabelSteps * grid.pixel * std::sqrt((1 - c * c) + ratio * ratio * c * c);  // mm
      OppositeNearest other(cloud, n, 2 * widest);
      index.findNeighbors(other, cloud.positions[i].data(), nanoflann::SearchParams());
      const double room = 0.5 * other.distance();  // half the plate's (or gap's) width
      thin[i] = room < step;
      cloud.tolerance[i] = float(std::max(1.0, std::min(step, room) / eps));
    }
  });
  LabelTolerance out;
  for (uint8_t t : thin) out.thin_points += t;
  std::vector<float> sorted = cloud.tolerance;
  if (!sorted.empty()) {
    std::nth_element(sorted.begin(), sorted.begin() + ptrdiff_t(sorted.size() / 2), sorted.end());
    out.median_factor = sorted[sorted.size() / 2];
  }
  return out;
}

}  // namespace mpumesh::mpu
