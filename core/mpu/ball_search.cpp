#include "mpu/ball_search.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace mpumesh::mpu {

BallSearch::BallSearch(const std::vector<Eigen::Vector3d>& pts, double cell) {
  MPUMESH_ASSERT(!pts.empty() && cell > 0 && std::isfinite(cell), "ball search needs points and a cell size");
  lo_ = pts[0];
  Eigen::Vector3d hi = lo_;
  for (const auto& p : pts) {
    lo_ = lo_.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d extent = hi - lo_;
  constexpr double kMaxCells = double(1 << 21);
  const double volume = std::max(extent.x(), cell) * std::max(extent.y(), cell) * std::max(extent.z(), cell);
  cell = std::max(cell, std::cbrt(volume / kMaxCells));
  inv_cell_ = 1.0 / cell;
  int64_t cells = 1;
  for (int d = 0; d < 3; ++d) {
    dims_[d] = int64_t(std::floor(extent[d] * inv_cell_)) + 1;
    cells *= dims_[d];
  }
  std::vector<uint32_t> of(pts.size());
  start_.assign(size_t(cells) + 1, 0);
  for (size_t i = 0; i < pts.size(); ++i) {
    int64_t c[3];
    for (int d = 0; d < 3; ++d) c[d] = std::clamp<int64_t>(int64_t((pts[i][d] - lo_[d]) * inv_cell_), 0, dims_[d] - 1);
    of[i] = uint32_t(c[0] + dims_[0] * (c[1] + dims_[1] * c[2]));
    ++start_[of[i] + 1];
  }
  for (int64_t c = 0; c < cells; ++c) start_[size_t(c) + 1] += start_[size_t(c)];
  x_.resize(pts.size());
  y_.resize(pts.size());
  z_.resize(pts.size());
  id_.resize(pts.size());
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < pts.size(); ++i) {
    const uint32_t k = fill[of[i]]++;
    x_[k] = pts[i].x();
    y_[k] = pts[i].y();
    z_[k] = pts[i].z();
    id_[k] = uint32_t(i);
  }
}

template <class Fn>
void BallSearch::for_runs(const Eigen::Vector3d& q, double r, Fn&& fn) const {
  // A little wider than r, so that rounding in q ± r can never leave out the cell of a
  // point on the sphere (the callers' distance tests decide; extra cells only cost).
  r = r * (1 + 1e-9) + 1e-12;
  int64_t a[3], b[3];
  for (int d = 0; d < 3; ++d) {
    const double u0 = std::floor((q[d] - r - lo_[d]) * inv_cell_), u1 = std::floor((q[d] + r - lo_[d]) * inv_cell_);
    a[d] = int64_t(std::max(u0, 0.0));
    b[d] = int64_t(std::min(u1, double(dims_[d] - 1)));
    if (a[d] > b[d]) return;
  }
  for (int64_t z = a[2]; z <= b[2]; ++z)
    for (int64_t y = a[1]; y <= b[1]; ++y) {
      const int64_t row = dims_[0] * (y + dims_[1] * z);
      fn(start_[size_t(row + a[0])], start_[size_t(row + b[0] + 1)]);
    }
}

template <class Fn>
void BallSearch::for_distances(const Eigen::Vector3d& q, double r, Fn&& fn) const {
  const double qx = q.x(), qy = q.y(), qz = q.z();
  for_runs(q, r, [&](uint32_t first, uint32_t last) {
    for (uint32_t k = first; k < last; ++k) {
      // (q - p)² summed x, y, z, as nanoflann's L2 metric does.
      const double dx = qx - x_[k], dy = qy - y_[k], dz = qz - z_[k];
      fn(dx * dx + dy * dy + dz * dz, id_[k]);
    }
  });
}

void BallSearch::ball(const Eigen::Vector3d& q, double r2, std::vector<uint32_t>& out) const {
  for_distances(q, std::sqrt(r2), [&](double d2, uint32_t id) {
    if (d2 < r2) out.push_back(id);
  });
}

void BallSearch::collect(const Eigen::Vector3d& q, double r, Near& near) const {
  const double r2 = r * r;
  near.points.clear();
  near.radius = r;
  for_distances(q, r, [&](double d2, uint32_t id) {
    if (d2 <= r2) near.points.push_back({d2, id});
  });
}

double BallSearch::kth_distance2(const Eigen::Vector3d& q, size_t k, double start, Near& near) const {
  MPUMESH_ASSERT(k >= 1 && k <= id_.size(), "kth_distance2: k out of range");
  // Once k points lie within r, the k-th smallest distance is among them (no point
  // farther than r can come before it).
  for (double r = start;; r *= 1.5) {
    collect(q, r, near);
    if (near.points.size() >= k) break;
  }
  // On a copy: `near` stays in the grid's order (see ball()).
  thread_local std::vector<double> d2;
  d2.resize(near.points.size());
  for (size_t j = 0; j < d2.size(); ++j) d2[j] = near.points[j].first;
  std::nth_element(d2.begin(), d2.begin() + ptrdiff_t(k - 1), d2.end());
  return d2[k - 1];
}

bool BallSearch::nearest_strict(const Eigen::Vector3d& q, size_t k, double radius, Near& near,
                                std::vector<uint32_t>& ids) const {
  ids.clear();
  collect(q, radius, near);
  if (near.points.size() < k + 1) return false;
  auto& pts = near.points;
  std::partial_sort(pts.begin(), pts.begin() + ptrdiff_t(k + 1), pts.end());
  for (size_t j = 0; j < k; ++j)
    if (!(pts[j].first < pts[j + 1].first)) return false;
  for (size_t j = 0; j < k; ++j) ids.push_back(pts[j].second);
  return true;
}

}  // namespace mpumesh::mpu
