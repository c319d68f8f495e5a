#include "particles/data_support.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace mpumesh::particles {

DataSupport::DataSupport(const std::vector<Eigen::Vector3d>& candidates, double reach, int max_cells) : reach_(reach) {
  MPUMESH_ASSERT(!candidates.empty() && reach > 0 && max_cells >= 1, "data support");
  Eigen::Vector3d lo = candidates[0], hi = lo;
  for (const auto& p : candidates) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo_ = lo - Eigen::Vector3d::Constant(reach);
  const Eigen::Vector3d size = hi - lo + Eigen::Vector3d::Constant(2 * reach);
  cell_ = std::max(0.5 * reach, size.maxCoeff() / max_cells);
  for (int d = 0; d < 3; ++d) dims_[size_t(d)] = std::max<int64_t>(1, int64_t(std::ceil(size[d] / cell_)));
  on_.assign(size_t(dims_[0] * dims_[1] * dims_[2]), 0);
  auto at = [&](int64_t x, int64_t y, int64_t z) -> uint8_t& { return on_[size_t(x + dims_[0] * (y + dims_[1] * z))]; };
  for (const auto& p : candidates) {
    const Eigen::Vector3d r = (p - lo_) / cell_;
    at(std::clamp<int64_t>(int64_t(r.x()), 0, dims_[0] - 1), std::clamp<int64_t>(int64_t(r.y()), 0, dims_[1] - 1),
       std::clamp<int64_t>(int64_t(r.z()), 0, dims_[2] - 1)) = 1;
  }
  // Dilation by k cells along each axis in turn (a cube of side 2k + 1 cells), k cells
  // covering the reach from anywhere in the candidate's cell.
  const int64_t k = int64_t(std::ceil(reach / cell_));
  std::vector<uint8_t> line;
  for (int d = 0; d < 3; ++d) {
    const int64_t n = dims_[size_t(d)];
    const int64_t stride = d == 0 ? 1 : d == 1 ? dims_[0] : dims_[0] * dims_[1];
    line.resize(size_t(n));
    for (size_t start = 0; start < on_.size(); ++start) {
      if ((int64_t(start) / stride) % n != 0) continue;  // one line per first cell along d
      for (int64_t i = 0; i < n; ++i) line[size_t(i)] = on_[size_t(int64_t(start) + i * stride)];
      int64_t last = -(k + 1);  // the last on cell at or before i, then after
      std::vector<uint8_t> out(size_t(n), 0);
      for (int64_t i = 0; i < n; ++i) {
        if (line[size_t(i)]) last = i;
        out[size_t(i)] = i - last <= k;
      }
      last = n + k + 1;
      for (int64_t i = n - 1; i >= 0; --i) {
        if (line[size_t(i)]) last = i;
        out[size_t(i)] = out[size_t(i)] || last - i <= k;
      }
      for (int64_t i = 0; i < n; ++i) on_[size_t(int64_t(start) + i * stride)] = out[size_t(i)];
    }
  }
}

bool DataSupport::near(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d r = (x - lo_) / cell_;
  int64_t c[3];
  for (int d = 0; d < 3; ++d) {
    if (!(r[d] >= 0)) return false;
    c[d] = int64_t(r[d]);
    if (c[d] >= dims_[size_t(d)]) return false;
  }
  return on_[size_t(c[0] + dims_[0] * (c[1] + dims_[1] * c[2]))] != 0;
}

}  // namespace mpumesh::particles
