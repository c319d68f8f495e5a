#include "mpu/mpu_eval_ref.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace mpumesh::mpu {

Sample evaluate(const MpuSurface& s, const Eigen::Vector3d& x) {
  Sample out;
  const Eigen::Vector3d rel = (x - s.box_min) / s.cell_size();
  const auto& dims = s.grid.dims;
  int64_t c[3];
  for (int d = 0; d < 3; ++d) {
    c[d] = int64_t(std::floor(rel[d]));
    if (c[d] < 0 || c[d] >= int64_t(dims[size_t(d)])) {
      out.f = s.box_size;
      return out;
    }
  }
  const size_t cell = size_t(c[0] + dims[0] * (c[1] + int64_t(dims[1]) * c[2]));
  // Sums about the first leaf's value f0 (f = f0 + N / D), as the shader takes them, where
  // float32 would lose the small f to the large Σ w Q.
  double f0 = 0, N = 0, D = 0;
  Eigen::Vector3d gN = Eigen::Vector3d::Zero(), gD = Eigen::Vector3d::Zero();
  Eigen::Matrix3d HN = Eigen::Matrix3d::Zero(), HD = Eigen::Matrix3d::Zero();
  for (uint32_t k = s.grid.offsets[cell]; k < s.grid.offsets[cell + 1]; ++k) {
    const Leaf& l = s.leaves[s.grid.leaf_ids[k]];
    const Eigen::Vector3d d = x - l.centre;
    const double r = d.norm();
    if (r >= l.radius) continue;
    double w, dw, d2w;
    bspline_weight(r, l.radius, w, dw, d2w);
    // ∇w = k1 d, Hw = k1 I + k2 d dᵀ; inside t <= 1/2 the weight is 3/4 - t², whose
    // k1 = dw/r = -2 s² stays finite at r = 0.
    const double sc = 1.5 / l.radius;
    const bool inner = sc * r <= 0.5;
    const double k1 = inner ? -2 * sc * sc : dw / r;
    const double k2 = inner ? 0.0 : (d2w - dw / r) / (r * r);
    const Eigen::Vector3d y = l.frame * d / l.radius;
    double q, gq[3], hq[6];
    local_poly(l.coeffs.data(), y.x(), y.y(), y.z(), q, gq, hq);
    // World units: Q = R q, ∇Q = Mᵀ ∇q, HQ = Mᵀ Hq M / R.
    const double Q = l.radius * q;
    const Eigen::Vector3d gQ = l.frame.transpose() * Eigen::Vector3d(gq[0], gq[1], gq[2]);
    Eigen::Matrix3d Hl;
    Hl << hq[0], hq[1], hq[2], hq[1], hq[3], hq[4], hq[2], hq[4], hq[5];
    const Eigen::Matrix3d HQ = l.frame.transpose() * Hl * l.frame / l.radius;
    if (out.leaves == 0) f0 = Q;
    const double Qs = Q - f0;
    const Eigen::Vector3d gw = k1 * d;
    const Eigen::Matrix3d Hw = k1 * Eigen::Matrix3d::Identity() + k2 * d * d.transpose();
    N += w * Qs;
    D += w;
    gN += Qs * gw + w * gQ;
    gD += gw;
    HN += Qs * Hw + gw * gQ.transpose() + gQ * gw.transpose() + w * HQ;
    HD += Hw;
    ++out.leaves;
  }
  if (!(D > 0)) {
    out.f = s.box_size;
    out.leaves = 0;
    return out;
  }
  const double fs = N / D;
  out.f = f0 + fs;
  out.g = (gN - fs * gD) / D;
  out.H = (HN - fs * HD - out.g * gD.transpose() - gD * out.g.transpose()) / D;
  return out;
}

double evaluate_f(const MpuSurface& s, const Eigen::Vector3d& x) {
  const Eigen::Vector3d rel = (x - s.box_min) / s.cell_size();
  const auto& dims = s.grid.dims;
  int64_t c[3];
  for (int d = 0; d < 3; ++d) {
    c[d] = int64_t(std::floor(rel[d]));
    if (c[d] < 0 || c[d] >= int64_t(dims[size_t(d)])) return s.box_size;
  }
  const size_t cell = size_t(c[0] + dims[0] * (c[1] + int64_t(dims[1]) * c[2]));
  double N = 0, D = 0;
  for (uint32_t k = s.grid.offsets[cell]; k < s.grid.offsets[cell + 1]; ++k) {
    const Leaf& l = s.leaves[s.grid.leaf_ids[k]];
    const Eigen::Vector3d d = x - l.centre;
    const double r = d.norm();
    if (r >= l.radius) continue;
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
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
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
