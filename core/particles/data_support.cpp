#include "particles/data_support.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace mpumesh::particles {

DataSupport::DataSupport(const std::vector<Eigen::Vector3d>& candidates, double reach, int max_cells)
    : points_(&candidates), reach_(reach) {
  MPUMESH_ASSERT(!candidates.empty() && reach > 0 && max_cells >= 1, "data support");
  Eigen::Vector3d lo = candidates[0], hi = lo;
  for (const auto& p : candidates) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo_ = lo;
  cell_ = std::max(reach, (hi - lo).maxCoeff() / max_cells);
  for (int d = 0; d < 3; ++d) dims_[size_t(d)] = int64_t(std::floor((hi[d] - lo[d]) / cell_)) + 1;
  const size_t cells = size_t(dims_[0] * dims_[1] * dims_[2]);
  auto cell_of = [&](const Eigen::Vector3d& p) {
    int64_t c[3];
    for (int d = 0; d < 3; ++d) c[d] = std::min<int64_t>(int64_t((p[d] - lo_[d]) / cell_), dims_[size_t(d)] - 1);
    return size_t(c[0] + dims_[0] * (c[1] + dims_[1] * c[2]));
  };
  first_.assign(cells + 1, 0);
  for (const auto& p : candidates) ++first_[cell_of(p) + 1];
  for (size_t c = 0; c < cells; ++c) first_[c + 1] += first_[c];
  ids_.resize(candidates.size());
  std::vector<uint32_t> fill(first_.begin(), first_.end() - 1);
  for (uint32_t i = 0; i < candidates.size(); ++i) ids_[fill[cell_of(candidates[i])]++] = i;
}

bool DataSupport::near(const Eigen::Vector3d& x) const {
  if (!x.allFinite()) return false;
  int64_t c[3];
  for (int d = 0; d < 3; ++d) {
    const double r = std::floor((x[d] - lo_[d]) / cell_);
    if (r < -1 || r > double(dims_[size_t(d)])) return false;  // no cell around it holds a candidate
    c[d] = int64_t(r);
  }
  const double r2 = reach_ * reach_;
  auto look = [&](int64_t x0, int64_t y0, int64_t z0) {
    if (x0 < 0 || y0 < 0 || z0 < 0 || x0 >= dims_[0] || y0 >= dims_[1] || z0 >= dims_[2]) return false;
    const size_t cell = size_t(x0 + dims_[0] * (y0 + dims_[1] * z0));
    for (uint32_t k = first_[cell]; k < first_[cell + 1]; ++k)
      if (((*points_)[ids_[k]] - x).squaredNorm() <= r2) return true;
    return false;
  };
  if (look(c[0], c[1], c[2])) return true;
  for (int64_t dz = -1; dz <= 1; ++dz)
    for (int64_t dy = -1; dy <= 1; ++dy)
      for (int64_t dx = -1; dx <= 1; ++dx)
        if ((dx || dy || dz) && look(c[0] + dx, c[1] + dy, c[2] + dz)) return true;
  return false;
}

}  // namespace mpumesh::particles
