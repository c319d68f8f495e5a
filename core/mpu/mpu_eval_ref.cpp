#include "mpu/mpu_eval_ref.h"

#include <tbb/parallel_for.h>

#include "common/error.h"

#include <algorithm>
#include <cmath>

namespace mpumesh::mpu {

namespace {

// The lookup-grid cell holding x, or false outside the bounding cube.
bool grid_cell(const MpuSurface& s, const Eigen::Vector3d& x, size_t& cell) {
  const Eigen::Vector3d rel = (x - s.box_min) / s.cell_size();
  const auto& dims = s.grid.dims;
  int64_t c[3];
  for (int d = 0; d < 3; ++d) {
    c[d] = int64_t(std::floor(rel[d]));
    if (c[d] < 0 || c[d] >= int64_t(dims[size_t(d)])) return false;
  }
  cell = size_t(c[0] + dims[0] * (c[1] + int64_t(dims[1]) * c[2]));
  return true;
}

// f, ∇f and (when kHessian) the Hessian; without it the Hessian terms are left out at
// compile time and out.H stays zero.
template <bool kHessian>
Sample evaluate_impl(const MpuSurface& s, const Eigen::Vector3d& x) {
  Sample out;
  size_t cell;
  if (!grid_cell(s, x, cell)) {
    out.f = s.box_size;
    return out;
  }
  // Sums about the first leaf's value f0 (f = f0 + N / D), as the shader takes them, where
  // float32 would lose the small f to the large Σ w Q. Symmetric 3x3 matrices are kept as
  // their 6 entries xx xy xz yy yz zz, and the loop is written out in scalars: it is the
  // CPU path's inner loop.
  double f0 = 0, N = 0, D = 0;
  double gN[3] = {0, 0, 0}, gD[3] = {0, 0, 0}, HN[6] = {0, 0, 0, 0, 0, 0}, HD[6] = {0, 0, 0, 0, 0, 0};
  const double px = x.x(), py = x.y(), pz = x.z();
  MPUMESH_ASSERT(s.grid.spheres.size() == s.leaves.size(), "MPU surface without its sphere index");
  for (uint32_t k = s.grid.offsets[cell]; k < s.grid.offsets[cell + 1]; ++k) {
    const uint32_t id = s.grid.leaf_ids[k];
    const Eigen::Vector4d& sp = s.grid.spheres[id];
    const double dx = px - sp[0], dy = py - sp[1], dz = pz - sp[2];
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (r2 >= sp[3]) continue;
    const Leaf& l = s.leaves[id];
    const double R = l.radius;
    const double r = std::sqrt(r2);
    double w, dw, d2w;
    bspline_weight(r, R, w, dw, d2w);
    // ∇w = k1 d, Hw = k1 I + k2 d dᵀ; inside t <= 1/2 the weight is 3/4 - t², whose
    // k1 = dw/r = -2 s² stays finite at r = 0.
    const double sc = 1.5 / R;
    const bool inner = sc * r <= 0.5;
    const double k1 = inner ? -2 * sc * sc : dw / r;
    const double k2 = inner ? 0.0 : (d2w - dw / r) / r2;
    const Eigen::Matrix3d& M = l.frame;
    const double invR = 1.0 / R;
    const double yu = (M(0, 0) * dx + M(0, 1) * dy + M(0, 2) * dz) * invR;
    const double yv = (M(1, 0) * dx + M(1, 1) * dy + M(1, 2) * dz) * invR;
    const double yw = (M(2, 0) * dx + M(2, 1) * dy + M(2, 2) * dz) * invR;
    double q, gq[3], hq[6];
    local_poly(l.coeffs.data(), yu, yv, yw, q, gq, hq);
    // World units: Q = R q, ∇Q = Mᵀ ∇q, HQ = Mᵀ Hq M / R.
    const double Q = R * q;
    double gQ[3], HQ[6] = {0, 0, 0, 0, 0, 0};
    for (int i = 0; i < 3; ++i) gQ[i] = M(0, i) * gq[0] + M(1, i) * gq[1] + M(2, i) * gq[2];
    static constexpr int kI[6] = {0, 0, 0, 1, 1, 2}, kJ[6] = {0, 1, 2, 1, 2, 2};
    if constexpr (kHessian) {
      double A[3][3];
      const double Hl[3][3] = {{hq[0], hq[1], hq[2]}, {hq[1], hq[3], hq[4]}, {hq[2], hq[4], hq[5]}};
      for (int a = 0; a < 3; ++a)
        for (int j = 0; j < 3; ++j) A[a][j] = Hl[a][0] * M(0, j) + Hl[a][1] * M(1, j) + Hl[a][2] * M(2, j);
      for (int e = 0; e < 6; ++e) {
        const int i = kI[e], j = kJ[e];
        HQ[e] = (M(0, i) * A[0][j] + M(1, i) * A[1][j] + M(2, i) * A[2][j]) * invR;
      }
    }
    if (out.leaves == 0) f0 = Q;
    const double Qs = Q - f0;
    const double d[3] = {dx, dy, dz};
    double gw[3];
    for (int i = 0; i < 3; ++i) gw[i] = k1 * d[i];
    N += w * Qs;
    D += w;
    for (int i = 0; i < 3; ++i) {
      gN[i] += Qs * gw[i] + w * gQ[i];
      gD[i] += gw[i];
    }
    if constexpr (kHessian)
      for (int e = 0; e < 6; ++e) {
        const int i = kI[e], j = kJ[e];
        const double Hw = (i == j ? k1 : 0.0) + k2 * d[i] * d[j];
        HN[e] += Qs * Hw + gw[i] * gQ[j] + gQ[i] * gw[j] + w * HQ[e];
        HD[e] += Hw;
      }
    ++out.leaves;
  }
  if (!(D > 0)) {
    out.f = s.box_size;
    out.leaves = 0;
    return out;
  }
  const double fs = N / D;
  out.f = f0 + fs;
  for (int i = 0; i < 3; ++i) out.g[i] = (gN[i] - fs * gD[i]) / D;
  static constexpr int kI[6] = {0, 0, 0, 1, 1, 2}, kJ[6] = {0, 1, 2, 1, 2, 2};
  if constexpr (kHessian)
    for (int e = 0; e < 6; ++e) {
      const int i = kI[e], j = kJ[e];
      const double h = (HN[e] - fs * HD[e] - out.g[i] * gD[j] - gD[i] * out.g[j]) / D;
      out.H(i, j) = h;
      out.H(j, i) = h;
    }
  return out;
}

}  // namespace

Sample evaluate(const MpuSurface& s, const Eigen::Vector3d& x) { return evaluate_impl<true>(s, x); }

Sample evaluate_fg(const MpuSurface& s, const Eigen::Vector3d& x) { return evaluate_impl<false>(s, x); }

double evaluate_f(const MpuSurface& s, const Eigen::Vector3d& x) {
  size_t cell;
  if (!grid_cell(s, x, cell)) return s.box_size;
  double N = 0, D = 0;
  for (uint32_t k = s.grid.offsets[cell]; k < s.grid.offsets[cell + 1]; ++k) {
    const uint32_t id = s.grid.leaf_ids[k];
    const Eigen::Vector4d& sp = s.grid.spheres[id];
    const double r2 = (x - sp.head<3>()).squaredNorm();
    if (r2 >= sp[3]) continue;  // the compact support test first, as in evaluate
    const Leaf& l = s.leaves[id];
    const Eigen::Vector3d d = x - l.centre;
    const double r = std::sqrt(r2);
    double w, dw, d2w;
    bspline_weight(r, l.radius, w, dw, d2w);
    const Eigen::Vector3d y = l.frame * d / l.radius;
    double q, gq[3], hq[6];
    local_poly(l.coeffs.data(), y.x(), y.y(), y.z(), q, gq, hq);
    N += w * l.radius * q;
    D += w;
  }
  return D > 0 ? N / D : s.box_size;
}

Curvature curvature(const Eigen::Vector3d& g, const Eigen::Matrix3d& H) {
  Curvature c;
  const double len = g.norm();
  if (!(len > 0)) return c;
  const Eigen::Vector3d n = g / len;
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
  const Eigen::Matrix3d G = -P * H * P / len;
  const double T = G.trace(), F = G.norm();
  const double disc = std::sqrt(std::max(2 * F * F - T * T, 0.0));
  c.k1 = 0.5 * (T + disc);
  c.k2 = 0.5 * (T - disc);
  c.gauss = c.k1 * c.k2;
  c.mean = 0.5 * (c.k1 + c.k2);
  return c;
}

std::vector<EvalRow> evaluate_all(const MpuSurface& s, const std::vector<Eigen::Vector3d>& points) {
  std::vector<EvalRow> rows(points.size());
  // Points are visited in the order of their lookup-grid cell, so that consecutive points
  // share their leaves in the cache (a surface of 10^5 leaves is tens of MB; in random
  // order each leaf read missed the cache).
  std::vector<std::pair<uint64_t, size_t>> order(points.size());
  const double inv_cell = 1.0 / s.cell_size();
  const auto& dims = s.grid.dims;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d rel = (points[i] - s.box_min) * inv_cell;
    uint64_t key = 0;
    for (int d = 2; d >= 0; --d)
      key = key * (dims[size_t(d)] + 1) + uint64_t(std::clamp(rel[d], -1.0, double(dims[size_t(d)])) + 1);
    order[i] = {key, i};
  }
  std::sort(order.begin(), order.end());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t o = r.begin(); o != r.end(); ++o) {
      const size_t i = order[o].second;
      const Sample e = evaluate(s, points[i]);
      const Curvature c = curvature(e.g, e.H);
      EvalRow& row = rows[i];
      for (int d = 0; d < 3; ++d) {
        row.x[d] = points[i][d];
        row.g[d] = e.g[d];
      }
      row.f = e.f;
      row.k1 = c.k1;
      row.k2 = c.k2;
      row.gauss = c.gauss;
      row.mean = c.mean;
    }
  });
  return rows;
}

}  // namespace mpumesh::mpu
