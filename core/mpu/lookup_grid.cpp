// The MPU surface's lookup grid (mpu_surface.h): per grid cell, the leaves whose ball
// touches it, which both backends read to find a point's leaves.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/eval_precision.h"
#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

void build_lookup_grid(MpuSurface& s, uint32_t n) {
  MPUMESH_ASSERT(n >= 1 && n <= 1024, "lookup grid size");
  s.grid.dims = {n, n, n};
  const double cell = s.box_size / double(n);
  const size_t cells = size_t(n) * n * n;
  // The z range of grid cells that leaf l's ball spans, and fn(cell index) for every cell
  // of slice z that the ball touches (ball-box test: the cell's closest point to the
  // centre lies inside the ball).
  auto z_range = [&](const Leaf& l, int64_t& lo, int64_t& hi) {
    lo = std::clamp<int64_t>(int64_t(std::floor((l.centre.z() - s.box_min.z() - l.radius) / cell)), 0, n - 1);
    hi = std::clamp<int64_t>(int64_t(std::floor((l.centre.z() - s.box_min.z() + l.radius) / cell)), 0, n - 1);
  };
  auto for_cells_in_slice = [&](const Leaf& l, int64_t z, auto&& fn) {
    const Eigen::Vector3d a = (l.centre - s.box_min - Eigen::Vector3d::Constant(l.radius)) / cell;
    const Eigen::Vector3d b = (l.centre - s.box_min + Eigen::Vector3d::Constant(l.radius)) / cell;
    int64_t lo[2], hi[2];
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::clamp<int64_t>(int64_t(std::floor(a[d])), 0, n - 1);
      hi[d] = std::clamp<int64_t>(int64_t(std::floor(b[d])), 0, n - 1);
    }
    // The squared distance from the centre to the cell's closest point is a sum of one
    // term per axis: each term is computed once per row and column, as the box test
    // computed it per cell (the same bits: the same grid).
    auto axis_term = [&](int d, int64_t i) {
      const double c = l.centre[d], lo_d = s.box_min[d] + cell * double(i);
      const double q = std::min(std::max(c, lo_d), lo_d + cell);
      return (q - c) * (q - c);
    };
    double tx[1024], ty[1024];
    for (int64_t x = lo[0]; x <= hi[0]; ++x) tx[x - lo[0]] = axis_term(0, x);
    for (int64_t y = lo[1]; y <= hi[1]; ++y) ty[y - lo[1]] = axis_term(1, y);
    const double tz = axis_term(2, z), r2 = l.radius * l.radius;
    for (int64_t y = lo[1]; y <= hi[1]; ++y)
      for (int64_t x = lo[0]; x <= hi[0]; ++x)
        if (tx[x - lo[0]] + ty[y - lo[1]] + tz < r2) fn(size_t(x + n * (y + n * z)));
  };
  // The leaves of each z slice (ascending), then count and fill (CSR) slice by slice in
  // parallel, so that leaf ids stay in ascending order per cell.
  std::vector<std::vector<uint32_t>> slice(n);
  for (uint32_t id = 0; id < s.leaves.size(); ++id) {
    int64_t lo, hi;
    z_range(s.leaves[id], lo, hi);
    for (int64_t z = lo; z <= hi; ++z) slice[size_t(z)].push_back(id);
  }
  s.grid.offsets.assign(cells + 1, 0);
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t z) {
    for (uint32_t id : slice[z]) for_cells_in_slice(s.leaves[id], z, [&](size_t c) { ++s.grid.offsets[c + 1]; });
  });
  for (size_t c = 0; c < cells; ++c) s.grid.offsets[c + 1] += s.grid.offsets[c];
  s.grid.leaf_ids.resize(s.grid.offsets[cells]);
  std::vector<uint32_t> fill(s.grid.offsets.begin(), s.grid.offsets.end() - 1);
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t z) {
    for (uint32_t id : slice[z])
      for_cells_in_slice(s.leaves[id], z, [&](size_t c) { s.grid.leaf_ids[fill[c]++] = id; });
  });
  index_spheres(s);
}

void index_spheres(MpuSurface& s) {
  s.grid.spheres.resize(s.leaves.size());
  for (size_t i = 0; i < s.leaves.size(); ++i) {
    const Leaf& l = s.leaves[i];
    s.grid.spheres[i] = Eigen::Vector4d(l.centre.x(), l.centre.y(), l.centre.z(), l.radius * l.radius);
  }
  s.grid.records32.clear();
  if (eval_precision() != EvalPrecision::kFloat) return;
  s.grid.records32.resize(s.leaves.size() * LookupGrid::kRecord32);
  for (size_t i = 0; i < s.leaves.size(); ++i) {
    const Leaf& l = s.leaves[i];
    float* to = s.grid.records32.data() + i * LookupGrid::kRecord32;
    for (int k = 0; k < 3; ++k) to[k] = float(l.centre[k]);
    to[3] = float(l.radius);
    for (int k = 0; k < 9; ++k) to[4 + k] = float(l.frame.data()[k]);
    for (size_t k = 0; k < l.coeffs.size(); ++k) to[13 + k] = float(l.coeffs[k]);
    to[LookupGrid::kRecord32 - 1] = 0;
  }
}

}  // namespace mpumesh::mpu
