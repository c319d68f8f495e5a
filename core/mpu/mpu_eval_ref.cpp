#include "mpu/mpu_eval_ref.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "common/error.h"
#include "common/eval_precision.h"
#include "common/simd_level.h"
#include "mpu/mpu_eval_simd.h"

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

// The evaluation runs in two passes over a point's leaves, so that its inner loops
// vectorise: the sphere test collects the leaves whose support holds the point (in the
// lookup grid's order) into chunks of up to kChunk; each chunk's leaf data are copied into
// structure-of-arrays form, each leaf's weight and polynomial terms are computed in a loop
// with no branches and no dependence between leaves, and the terms are summed in kLanes
// running sums (leaf j into sum j mod kLanes, the sums added in a fixed order at the end),
// so the result is the same bytes whatever vector width the compiler uses.
// Order 0: f only; 1: f and ∇f; 2: f, ∇f and the blended Hessian Hb; 3: and the Hessian H.
constexpr int kLanes = 8;
constexpr int kChunk = 32;  // a multiple of kLanes

// The leaves of one chunk, as structure of arrays.
struct ChunkIn {
  alignas(64) double dx[kChunk], dy[kChunk], dz[kChunk], r2[kChunk], R[kChunk];
  alignas(64) double M[9][kChunk];
  alignas(64) double c[kTerms][kChunk];
};

// Each leaf's terms at the point: weight w, its gradient gw and Hessian Hw, and the leaf
// function Q with its gradient gQ and Hessian HQ, in world units. Symmetric 3x3 matrices
// are kept as their 6 entries xx xy xz yy yz zz.
struct ChunkTerms {
  alignas(64) double w[kChunk], Q[kChunk];
  alignas(64) double gw[3][kChunk], gQ[3][kChunk];
  alignas(64) double Hw[6][kChunk], HQ[6][kChunk];
};

// Running sums about the first leaf's value f0 (f = f0 + N / D, as the shader takes them,
// where float32 would lose the small f to the large Σ w Q).
struct Sums {
  alignas(64) double N[kLanes] = {}, D[kLanes] = {};
  alignas(64) double gN[3][kLanes] = {}, gD[3][kLanes] = {};
  alignas(64) double HbN[6][kLanes] = {};
  alignas(64) double HN[6][kLanes] = {}, HD[6][kLanes] = {};
};

constexpr int kI[6] = {0, 0, 0, 1, 1, 2}, kJ[6] = {0, 1, 2, 1, 2, 2};

template <int kOrder>
void chunk_terms(const ChunkIn& __restrict in, int n, ChunkTerms& __restrict t) {
  for (int j = 0; j < n; ++j) {
    const double R = in.R[j], r2 = in.r2[j], dx = in.dx[j], dy = in.dy[j], dz = in.dz[j];
    const double r = std::sqrt(r2);
    double w, dw, d2w;
    bspline_weight(r, R, w, dw, d2w);
    const double invR = 1.0 / R;
    const double M[9] = {in.M[0][j], in.M[1][j], in.M[2][j], in.M[3][j], in.M[4][j],
                         in.M[5][j], in.M[6][j], in.M[7][j], in.M[8][j]};
    const double yu = (M[0] * dx + M[1] * dy + M[2] * dz) * invR;
    const double yv = (M[3] * dx + M[4] * dy + M[5] * dz) * invR;
    const double yw = (M[6] * dx + M[7] * dy + M[8] * dz) * invR;
    double q, gq[3], hq[6];
    local_poly<double, kChunk>(&in.c[0][j], yu, yv, yw, q, gq, hq);
    t.w[j] = w;
    t.Q[j] = R * q;  // world units: Q = R q, ∇Q = Mᵀ ∇q, HQ = Mᵀ Hq M / R
    if constexpr (kOrder >= 1) {
      // ∇w = k1 d, Hw = k1 I + k2 d dᵀ; inside t <= 1/2 the weight is 3/4 - t², whose
      // k1 = dw/r = -2 s² stays finite at r = 0.
      const double sc = 1.5 * invR;
      const bool inner = sc * r <= 0.5;
      const double k1 = inner ? -2 * sc * sc : dw / r;
      const double d[3] = {dx, dy, dz};
      for (int i = 0; i < 3; ++i) {
        t.gw[i][j] = k1 * d[i];
        t.gQ[i][j] = M[i] * gq[0] + M[3 + i] * gq[1] + M[6 + i] * gq[2];
      }
      if constexpr (kOrder >= 2) {
        const double Hl[3][3] = {{hq[0], hq[1], hq[2]}, {hq[1], hq[3], hq[4]}, {hq[2], hq[4], hq[5]}};
        double A[3][3];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) A[a][b] = Hl[a][0] * M[b] + Hl[a][1] * M[3 + b] + Hl[a][2] * M[6 + b];
        for (int e = 0; e < 6; ++e) {
          const int i = kI[e], k = kJ[e];
          t.HQ[e][j] = (M[i] * A[0][k] + M[3 + i] * A[1][k] + M[6 + i] * A[2][k]) * invR;
        }
        if constexpr (kOrder >= 3) {
          const double k2 = inner ? 0.0 : (d2w - dw / r) / r2;
          for (int e = 0; e < 6; ++e) {
            const int i = kI[e], k = kJ[e];
            t.Hw[e][j] = (i == k ? k1 : 0.0) + k2 * d[i] * d[k];
          }
        }
      }
    }
  }
}

template <int kOrder>
void chunk_sums(const ChunkTerms& __restrict t, int n, double f0, Sums& __restrict s) {
  for (int b = 0; b < n; b += kLanes)
    for (int l = 0; l < kLanes; ++l) {
      const int j = b + l;
      const double w = t.w[j], Qs = t.Q[j] - f0;
      s.N[l] += w * Qs;
      s.D[l] += w;
      if constexpr (kOrder >= 1)
        for (int i = 0; i < 3; ++i) {
          s.gN[i][l] += Qs * t.gw[i][j] + w * t.gQ[i][j];
          s.gD[i][l] += t.gw[i][j];
        }
      if constexpr (kOrder >= 2)
        for (int e = 0; e < 6; ++e) s.HbN[e][l] += w * t.HQ[e][j];
      if constexpr (kOrder >= 3)
        for (int e = 0; e < 6; ++e) {
          const int i = kI[e], k = kJ[e];
          s.HN[e][l] += Qs * t.Hw[e][j] + t.gw[i][j] * t.gQ[k][j] + t.gQ[i][j] * t.gw[k][j] + w * t.HQ[e][j];
          s.HD[e][l] += t.Hw[e][j];
        }
    }
}

double lane_total(const double (&v)[kLanes]) {
  double a = 0;
  for (int l = 0; l < kLanes; ++l) a += v[l];
  return a;
}

// The vector paths (mpu_eval_simd.h) give evaluate_impl's bytes, with fewer instructions;
// the single-precision ones (common/eval_precision.h) replace it. Sets `out` and returns
// true where one runs; false at the generic level in double precision, and where a
// kernel declines a lookup cell of more candidates than it buffers (evaluate_impl then
// evaluates the point).
template <int kOrder>
bool vector_path(const MpuSurface& s, const Eigen::Vector3d& x, Sample& out) {
  const SimdLevel level = simd_level();
  const bool single = eval_precision() == EvalPrecision::kFloat;
  if (!single && level == SimdLevel::kGeneric) return false;
  MPUMESH_ASSERT(s.grid.spheres.size() == s.leaves.size(), "MPU surface without its sphere index");
  const simd::EvalView view = simd::make_view(s);
  MPUMESH_ASSERT(!single || view.records32 || s.leaves.empty(),
                 "MPU surface indexed before single precision was chosen (mpu::index_spheres)");
  const simd::EvalOut o = !single ? (level == SimdLevel::kAvx512 ? simd::evaluate_avx512(view, x.data(), kOrder)
                                                                 : simd::evaluate_avx2(view, x.data(), kOrder))
                          : level == SimdLevel::kAvx512 ? simd::evaluate_f32_avx512(view, x.data(), kOrder)
                          : level == SimdLevel::kAvx2   ? simd::evaluate_f32_avx2(view, x.data(), kOrder)
                                                        : simd::evaluate_f32_generic(view, x.data(), kOrder);
  if (!o.handled) return false;
  out.f = o.f;
  out.leaves = o.leaves;
  if constexpr (kOrder >= 1) out.g = Eigen::Vector3d(o.g[0], o.g[1], o.g[2]);
  for (int e = 0; e < 6; ++e) {
    if constexpr (kOrder >= 2) out.Hb(kI[e], kJ[e]) = out.Hb(kJ[e], kI[e]) = o.Hb[e];
    if constexpr (kOrder >= 3) out.H(kI[e], kJ[e]) = out.H(kJ[e], kI[e]) = o.H[e];
  }
  return true;
}

template <int kOrder>
Sample evaluate_impl(const MpuSurface& s, const Eigen::Vector3d& x) {
  Sample out;
  if (vector_path<kOrder>(s, x, out)) return out;
  size_t cell;
  if (!grid_cell(s, x, cell)) {
    out.f = s.box_size;
    return out;
  }
  MPUMESH_ASSERT(s.grid.spheres.size() == s.leaves.size(), "MPU surface without its sphere index");
  const double px = x.x(), py = x.y(), pz = x.z();
  ChunkIn in;
  ChunkTerms t;
  Sums sums;
  double f0 = 0;
  int n = 0;
  uint32_t ids[kChunk];
  auto flush = [&] {
    for (int j = 0; j < n; ++j) {
      const Leaf& l = s.leaves[ids[j]];
      in.R[j] = l.radius;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) in.M[3 * a + b][j] = l.frame(a, b);
      for (int e = 0; e < kTerms; ++e) in.c[e][j] = l.coeffs[size_t(e)];
    }
    // Pad to whole lanes with leaves far outside their support (zero weight and terms).
    const int padded = (n + kLanes - 1) / kLanes * kLanes;
    for (int j = n; j < padded; ++j) {
      in.dx[j] = 4 * in.R[0];
      in.dy[j] = in.dz[j] = 0;
      in.r2[j] = in.dx[j] * in.dx[j];
      in.R[j] = in.R[0];
      for (int e = 0; e < 9; ++e) in.M[e][j] = in.M[e][0];
      for (int e = 0; e < kTerms; ++e) in.c[e][j] = in.c[e][0];
    }
    chunk_terms<kOrder>(in, padded, t);
    if (out.leaves == 0) f0 = t.Q[0];
    chunk_sums<kOrder>(t, padded, f0, sums);
    out.leaves += n;
    n = 0;
  };
  // The compact support test, which most candidates fail: written without a branch on
  // its outcome (a hit only advances n), as it is hard to predict.
  for (uint32_t k = s.grid.offsets[cell]; k < s.grid.offsets[cell + 1]; ++k) {
    const uint32_t id = s.grid.leaf_ids[k];
    const Eigen::Vector4d& sp = s.grid.spheres[id];
    const double dx = px - sp[0], dy = py - sp[1], dz = pz - sp[2];
    const double r2 = dx * dx + dy * dy + dz * dz;
    ids[n] = id;
    in.dx[n] = dx;
    in.dy[n] = dy;
    in.dz[n] = dz;
    in.r2[n] = r2;
    n += r2 < sp[3];
    if (n == kChunk) flush();
  }
  if (n > 0) flush();
  const double D = lane_total(sums.D);
  if (!(D > 0)) {
    out.f = s.box_size;
    out.leaves = 0;
    return out;
  }
  const double fs = lane_total(sums.N) / D;
  out.f = f0 + fs;
  if constexpr (kOrder >= 1) {
    double gD[3];
    for (int i = 0; i < 3; ++i) {
      gD[i] = lane_total(sums.gD[i]);
      out.g[i] = (lane_total(sums.gN[i]) - fs * gD[i]) / D;
    }
    for (int e = 0; e < 6; ++e) {
      const int i = kI[e], j = kJ[e];
      if constexpr (kOrder >= 2) out.Hb(i, j) = out.Hb(j, i) = lane_total(sums.HbN[e]) / D;
      if constexpr (kOrder >= 3)
        out.H(i, j) = out.H(j, i) =
            (lane_total(sums.HN[e]) - fs * lane_total(sums.HD[e]) - out.g[i] * gD[j] - gD[i] * out.g[j]) / D;
    }
  }
  return out;
}

}  // namespace

Sample evaluate(const MpuSurface& s, const Eigen::Vector3d& x) { return evaluate_impl<2>(s, x); }

Sample evaluate_hessian(const MpuSurface& s, const Eigen::Vector3d& x) { return evaluate_impl<3>(s, x); }

Sample evaluate_fg(const MpuSurface& s, const Eigen::Vector3d& x) { return evaluate_impl<1>(s, x); }

double evaluate_f(const MpuSurface& s, const Eigen::Vector3d& x) { return evaluate_impl<0>(s, x).f; }

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

std::vector<size_t> cache_order(const MpuSurface& s, const std::vector<Eigen::Vector3d>& points) {
  // In parallel: the keys are distinct (the index breaks ties), so the order is one. (The
  // triangulation's first call orders 300,000 circumcentres on the sample CT.)
  std::vector<std::pair<uint64_t, size_t>> key(points.size());
  const double inv_cell = 1.0 / s.cell_size();
  const auto& dims = s.grid.dims;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3d rel = (points[i] - s.box_min) * inv_cell;
      uint64_t k = 0;
      for (int d = 2; d >= 0; --d)
        k = k * (dims[size_t(d)] + 1) + uint64_t(std::clamp(rel[d], -1.0, double(dims[size_t(d)])) + 1);
      key[i] = {k, i};
    }
  });
  tbb::parallel_sort(key.begin(), key.end());
  std::vector<size_t> order(points.size());
  tbb::parallel_for(size_t(0), order.size(), [&](size_t o) { order[o] = key[o].second; });
  return order;
}

std::vector<EvalRow> evaluate_all(const MpuSurface& s, const std::vector<Eigen::Vector3d>& points) {
  std::vector<EvalRow> rows(points.size());
  const std::vector<size_t> order = cache_order(s, points);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t o = r.begin(); o != r.end(); ++o) {
      const size_t i = order[o];
      const Sample e = evaluate(s, points[i]);
      const Curvature c = curvature(e);
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
