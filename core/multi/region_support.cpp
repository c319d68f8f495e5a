#include "multi/region_support.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mpumesh::multi {
namespace {

// A running maximum over 2 k + 1 voxels along one axis of a box of `dims`, in place.
void dilate_axis(std::vector<uint8_t>& m, const std::array<int64_t, 3>& dims, int axis, int k) {
  const int64_t stride = axis == 0 ? 1 : axis == 1 ? dims[0] : dims[0] * dims[1];
  const int64_t n = dims[size_t(axis)];
  std::vector<uint8_t> line(static_cast<size_t>(n)), out(static_cast<size_t>(n));
  const int64_t lines = dims[0] * dims[1] * dims[2] / n;
  for (int64_t l = 0; l < lines; ++l) {
    // The line's first voxel: every index but `axis`'s.
    int64_t start;
    if (axis == 0) start = l * dims[0];
    else if (axis == 1) start = (l % dims[0]) + (l / dims[0]) * dims[0] * dims[1];
    else start = l;
    for (int64_t i = 0; i < n; ++i) line[size_t(i)] = m[size_t(start + i * stride)];
    for (int64_t i = 0; i < n; ++i) {
      uint8_t v = 0;
      for (int64_t j = std::max<int64_t>(0, i - k); j <= std::min(n - 1, i + k) && !v; ++j) v = line[size_t(j)];
      out[size_t(i)] = v;
    }
    for (int64_t i = 0; i < n; ++i) m[size_t(start + i * stride)] = out[size_t(i)];
  }
}

}  // namespace

RegionSupport::RegionSupport(const Volume& map, const std::vector<int64_t>& labels)
    : dims_(map.dims), origin_(map.origin), spacing_(map.spacing) {
  to_index_ = map.direction.inverse();
  std::map<int64_t, int> region;
  for (size_t k = 0; k < labels.size(); ++k) region[labels[k]] = int(k) + 1;
  const size_t n = map.voxels.size();
  std::vector<uint16_t> which(n, 0);  // labels_to_mesh allows at most kMaxLabels (1000)
  boxes_.assign(labels.size() + 1, {});
  boxes_[0] = {{0, 0, 0}, dims_};
  for (size_t r = 1; r < boxes_.size(); ++r) boxes_[r] = {{dims_[0], dims_[1], dims_[2]}, {0, 0, 0}};
  for (int64_t k = 0; k < dims_[2]; ++k)
    for (int64_t j = 0; j < dims_[1]; ++j)
      for (int64_t i = 0; i < dims_[0]; ++i) {
        const size_t at = size_t(map.index(i, j, k));
        const auto it = region.find(std::lround(map.voxels[at]));
        if (it == region.end()) continue;
        which[at] = uint16_t(it->second);
        Box& b = boxes_[size_t(it->second)];
        const int64_t idx[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) {
          b.lo[size_t(d)] = std::min(b.lo[size_t(d)], idx[d]);
          b.hi[size_t(d)] = std::max(b.hi[size_t(d)], idx[d] + 1);
        }
      }
  bits_.resize(boxes_.size());
  for (size_t r = 0; r < boxes_.size(); ++r) {
    Box& b = boxes_[r];
    for (int d = 0; d < 3; ++d) {
      b.lo[size_t(d)] = std::max<int64_t>(0, b.lo[size_t(d)] - kSupportVoxels);
      b.hi[size_t(d)] = std::min(dims_[size_t(d)], b.hi[size_t(d)] + kSupportVoxels);
      if (b.hi[size_t(d)] <= b.lo[size_t(d)]) b.hi[size_t(d)] = b.lo[size_t(d)];
    }
    const std::array<int64_t, 3> bd = {b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]};
    const size_t cells = size_t(bd[0] * bd[1] * bd[2]);
    if (cells == 0) continue;
    std::vector<uint8_t> m(cells);
    for (int64_t k = 0; k < bd[2]; ++k)
      for (int64_t j = 0; j < bd[1]; ++j)
        for (int64_t i = 0; i < bd[0]; ++i)
          m[size_t(i + bd[0] * (j + bd[1] * k))] =
              which[size_t(map.index(i + b.lo[0], j + b.lo[1], k + b.lo[2]))] == r;
    for (int axis = 0; axis < 3; ++axis) dilate_axis(m, bd, axis, kSupportVoxels);
    auto& bits = bits_[r];
    bits.assign((cells + 63) / 64, 0);
    for (size_t i = 0; i < cells; ++i)
      if (m[i]) bits[i / 64] |= uint64_t(1) << (i % 64);
  }
}

bool RegionSupport::voxel_of(const Eigen::Vector3d& p, std::array<int64_t, 3>& idx) const {
  const Eigen::Vector3d ijk = (to_index_ * (p - origin_)).cwiseQuotient(spacing_);
  for (int d = 0; d < 3; ++d) {
    const double x = std::round(ijk[d]);
    if (!(x >= 0 && x < double(dims_[size_t(d)]))) return false;
    idx[size_t(d)] = int64_t(x);
  }
  return true;
}

bool RegionSupport::allows(int r, const Eigen::Vector3d& p) const {
  std::array<int64_t, 3> idx;
  if (!voxel_of(p, idx)) return r == 0;
  const Box& b = boxes_[size_t(r)];
  for (int d = 0; d < 3; ++d)
    if (idx[size_t(d)] < b.lo[size_t(d)] || idx[size_t(d)] >= b.hi[size_t(d)]) return false;
  const int64_t bx = b.hi[0] - b.lo[0], by = b.hi[1] - b.lo[1];
  const size_t v = size_t((idx[0] - b.lo[0]) + bx * ((idx[1] - b.lo[1]) + by * (idx[2] - b.lo[2])));
  return (bits_[size_t(r)][v / 64] >> (v % 64)) & 1;
}

}  // namespace mpumesh::multi
