// A uniform grid over a point set for fixed-radius neighbour queries: cells of the query
// radius, points sorted by cell (counting sort), so the neighbours of a point lie in the
// contiguous ranges of its 27 surrounding cells. Cheaper than a k-d tree when every point
// asks for the same radius.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace mpumesh {

class NeighbourGrid {
 public:
  NeighbourGrid(const std::vector<Eigen::Vector3d>& pts, double radius) : pts_(pts), r2_(radius * radius) {
    lo_ = Eigen::Vector3d::Constant(INFINITY);
    Eigen::Vector3d hi = Eigen::Vector3d::Constant(-INFINITY);
    for (const auto& p : pts) {
      lo_ = lo_.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    if (pts.empty()) lo_ = hi = Eigen::Vector3d::Zero();
    inv_ = 1.0 / radius;
    for (int d = 0; d < 3; ++d) dims_[size_t(d)] = int64_t(std::floor((hi[d] - lo_[d]) * inv_)) + 1;
    const int64_t cells = dims_[0] * dims_[1] * dims_[2];
    start_.assign(size_t(cells) + 1, 0);
    std::vector<int64_t> cell(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
      cell[i] = cell_of(pts[i]);
      ++start_[size_t(cell[i]) + 1];
    }
    for (int64_t c = 0; c < cells; ++c) start_[size_t(c) + 1] += start_[size_t(c)];
    order_.resize(pts.size());
    std::vector<int64_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < pts.size(); ++i) order_[size_t(fill[size_t(cell[i])]++)] = uint32_t(i);
  }

  // Calls f(j) for every point j within the radius of q (q itself included if it is one).
  template <class F>
  void for_each_within(const Eigen::Vector3d& q, F&& f) const {
    std::array<int64_t, 3> c;
    for (int d = 0; d < 3; ++d) c[size_t(d)] = int64_t(std::floor((q[d] - lo_[d]) * inv_));
    for (int64_t z = std::max<int64_t>(c[2] - 1, 0); z <= std::min(c[2] + 1, dims_[2] - 1); ++z)
      for (int64_t y = std::max<int64_t>(c[1] - 1, 0); y <= std::min(c[1] + 1, dims_[1] - 1); ++y) {
        const int64_t x0 = std::max<int64_t>(c[0] - 1, 0), x1 = std::min(c[0] + 1, dims_[0] - 1);
        if (x0 > x1) continue;
        const int64_t row = dims_[0] * (y + dims_[1] * z);
        // Cells x0..x1 of one row are contiguous in the sorted order.
        for (int64_t s = start_[size_t(row + x0)]; s < start_[size_t(row + x1 + 1)]; ++s) {
          const uint32_t j = order_[size_t(s)];
          if ((pts_[j] - q).squaredNorm() <= r2_) f(j);
        }
      }
  }

  // Points in cell order: visiting them in this order keeps neighbouring queries in cache.
  const std::vector<uint32_t>& order() const { return order_; }

 private:
  int64_t cell_of(const Eigen::Vector3d& p) const {
    int64_t idx[3];
    for (int d = 0; d < 3; ++d)
      idx[d] = std::clamp<int64_t>(int64_t(std::floor((p[d] - lo_[d]) * inv_)), 0, dims_[size_t(d)] - 1);
    return idx[0] + dims_[0] * (idx[1] + dims_[1] * idx[2]);
  }

  const std::vector<Eigen::Vector3d>& pts_;
  double r2_, inv_;
  Eigen::Vector3d lo_;
  std::array<int64_t, 3> dims_{1, 1, 1};
  std::vector<int64_t> start_;
  std::vector<uint32_t> order_;
};

}  // namespace mpumesh
