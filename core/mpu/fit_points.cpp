#include "mpu/fit_points.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "common/error.h"

namespace mpumesh::mpu {

// Found with an open-addressing table of the kept points, keyed by their coordinates'
// bits (-0 as +0, since they compare equal): cheaper than sorting the points by position.
PointCloud without_duplicates(const PointCloud& in, int64_t* removed) {
  auto bits = [](double v) {
    uint64_t u;
    v += 0.0;  // -0 becomes +0
    std::memcpy(&u, &v, sizeof u);
    return u;
  };
  auto hash = [&](const Eigen::Vector3d& p) {
    uint64_t h = bits(p.x()) * 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 29) ^ bits(p.y())) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 32) ^ bits(p.z())) * 0x94D049BB133111EBull;
    return h ^ (h >> 31);
  };
  size_t slots = 16;
  while (slots < 2 * in.size()) slots *= 2;
  std::vector<uint32_t> table(slots, UINT32_MAX);  // a kept point's index, or empty
  PointCloud out;
  out.positions.reserve(in.size());
  out.normals.reserve(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const Eigen::Vector3d& p = in.positions[i];
    size_t at = hash(p) & (slots - 1);
    while (table[at] != UINT32_MAX && in.positions[table[at]] != p) at = (at + 1) & (slots - 1);
    if (table[at] != UINT32_MAX) continue;  // a repeat of a kept point
    table[at] = uint32_t(i);
    out.positions.push_back(p);
    out.normals.push_back(in.normals[i]);
    if (!in.tolerance.empty()) out.tolerance.push_back(in.tolerance[i]);
  }
  *removed = int64_t(in.size() - out.size());
  return out;
}

void check_not_flat(const PointCloud& c) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : c.positions) mean += p;
  mean /= double(c.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : c.positions) cov += (p - mean) * (p - mean).transpose();
  cov /= double(c.size());
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues();
  const double thick = std::sqrt(std::max(ev[0], 0.0)), wide = std::sqrt(std::max(ev[2], 0.0));
  if (!(thick > 1e-4 * wide) || !(wide > 0))
    throw InputError("fit: the points lie on one plane (spread " + std::to_string(thick) + " mm across it, " +
                     std::to_string(wide) + " mm along it): a closed surface needs points around a volume");
}

}  // namespace mpumesh::mpu
