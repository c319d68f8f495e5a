#include "multi/region_support.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mpumesh::multi {
namespace {

// A running maximum over 2 k + 1 voxels along one axis, in place.
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
  std::vector<uint8_t> which(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const auto it = region.find(std::lround(map.voxels[i]));
    which[i] = uint8_t(it == region.end() ? 0 : it->second);
  }
  bits_.resize(labels.size() + 1);
  std::vector<uint8_t> m(n);
  for (int r = 0; r <= int(labels.size()); ++r) {
    for (size_t i = 0; i < n; ++i) m[i] = which[i] == r;
    for (int axis = 0; axis < 3; ++axis) dilate_axis(m, dims_, axis, kSupportVoxels);
    auto& b = bits_[size_t(r)];
    b.assign((n + 63) / 64, 0);
    for (size_t i = 0; i < n; ++i)
      if (m[i]) b[i / 64] |= uint64_t(1) << (i % 64);
  }
}

int64_t RegionSupport::voxel_of(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d ijk = (to_index_ * (p - origin_)).cwiseQuotient(spacing_);
  int64_t idx[3];
  for (int d = 0; d < 3; ++d) {
    const double x = std::round(ijk[d]);
    if (!(x >= 0 && x < double(dims_[size_t(d)]))) return -1;
    idx[d] = int64_t(x);
  }
  return idx[0] + dims_[0] * (idx[1] + dims_[1] * idx[2]);
}

bool RegionSupport::allows(int r, const Eigen::Vector3d& p) const {
  const int64_t v = voxel_of(p);
  if (v < 0) return r == 0;
  return (bits_[size_t(r)][size_t(v) / 64] >> (size_t(v) % 64)) & 1;
}

}  // namespace mpumesh::multi
