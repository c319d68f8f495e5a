// The vector evaluation kernel of mpu_eval_simd.h, written once over an instruction-set
// traits class I (mpu_eval_avx512.cpp, mpu_eval_avx2.cpp, mpu_eval_f32_generic.cpp) whose
// vectors hold kLanes numbers of type T (8 doubles, or 16 floats):
//   T, kLanes, V, Mask; set1, zero, add, sub, mul, div, sqrt, lt, le, sel(m, t, f) = m ? t : f,
//   keep(m, a) = m ? a : +0, first(a) = lane 0, store(p, a) (kLanes T's),
//   lanes_from(k): the mask of lanes >= k,
//   record(view, id): leaf id's record, 36 T's (mpu_eval_simd.h),
//   load_leaves(p[kLanes], F[36]): F[k] lane l = p[l][k];
// and Support, the double-precision traits (itself for the double kernels) whose
//   support(spheres, ids, count <= 8, px, py, pz, out) appends to out, in order, the ids
//     whose sphere (cx, cy, cz, R²) holds the point (r² < R²), and returns how many.
// The including file defines MPUMESH_SIMD_TARGET (the target attribute) first. Every
// operation below is the one mpu_eval_ref.cpp does, in its order (see the header there),
// so that the double kernels' results are its bytes, and the float kernels' the same
// bytes at every level. No lambdas: they would not carry the target.
#pragma once

#include <cmath>
#include <cstdint>

#include "mpu/mpu_eval_simd.h"

namespace mpumesh::mpu::simd {

template <class I>
struct Sums {
  typename I::V N, D, gN[3], gD[3], HbN[6], HN[6], HD[6];
};

template <class I>
MPUMESH_SIMD_TARGET inline double lane_total(typename I::V a) {
  typename I::T v[I::kLanes];
  I::store(v, a);
  double t = 0;
  for (int l = 0; l < I::kLanes; ++l) t += v[l];
  return t;
}

// One block of kLanes leaves at the point: the offsets from their centres, their weights
// (bspline_weight) and the point in each leaf's scaled frame (u, v, w), with its
// coefficients c (F + 13).
template <class I>
struct LeafBlock {
  using V = typename I::V;
  V F[36];
  V dx, dy, dz, r2, r, R, invR;
  V w, dw, d2w;
  V M[9];  // frame rows u, v, w; F holds the frame column-major
  V u, v, ww, u2, v2, uv;
  const V* c;
};

#define MPUMESH_SIMD_STEP MPUMESH_SIMD_TARGET __attribute__((always_inline)) inline

// The leaves' data, and the point's offsets from their centres: lanes from `pad_from` on
// are padding, 4 R away along x, as the reference pads.
template <class I>
MPUMESH_SIMD_STEP void load_block(const typename I::T* const* p, const double x[3], int pad_from, double pad_dx,
                                  LeafBlock<I>& b) {
  I::load_leaves(p, b.F);
  b.dx = I::sub(I::set1(x[0]), b.F[0]), b.dy = I::sub(I::set1(x[1]), b.F[1]), b.dz = I::sub(I::set1(x[2]), b.F[2]);
  if (pad_from < I::kLanes) {
    const typename I::Mask pad = I::lanes_from(pad_from);
    b.dx = I::sel(pad, I::set1(pad_dx), b.dx);
    b.dy = I::sel(pad, I::zero(), b.dy);
    b.dz = I::sel(pad, I::zero(), b.dz);
  }
  b.r2 = I::add(I::add(I::mul(b.dx, b.dx), I::mul(b.dy, b.dy)), I::mul(b.dz, b.dz));
  b.R = b.F[3];
  b.r = I::sqrt(b.r2);
}

// The weight w(r) = b(1.5 r / R) and its first two derivatives in r (bspline_weight).
template <class I>
MPUMESH_SIMD_STEP void block_weights(LeafBlock<I>& b) {
  using V = typename I::V;
  using Mask = typename I::Mask;
  const V c15 = I::set1(1.5), c05 = I::set1(0.5), m2 = I::set1(-2.0);
  const V sw = I::div(c15, b.R), t = I::mul(sw, b.r), tm = I::sub(t, c15);
  const V inner_w = I::sub(I::set1(0.75), I::mul(t, t)), outer_w = I::mul(I::mul(c05, tm), tm);
  const Mask in = I::le(t, c05), sup = I::lt(t, c15);
  b.w = I::keep(sup, I::sel(in, inner_w, outer_w));
  b.dw = I::keep(sup, I::sel(in, I::mul(I::mul(m2, t), sw), I::mul(tm, sw)));
  b.d2w = I::keep(sup, I::sel(in, I::mul(I::mul(m2, sw), sw), I::mul(sw, sw)));
  b.invR = I::div(I::set1(1.0), b.R);
}

// The point in each leaf's frame, scaled by 1 / R.
template <class I>
MPUMESH_SIMD_STEP void block_frame(LeafBlock<I>& b) {
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) b.M[3 * a + k] = b.F[4 + a + 3 * k];
  const auto* M = b.M;
  b.u = I::mul(I::add(I::add(I::mul(M[0], b.dx), I::mul(M[1], b.dy)), I::mul(M[2], b.dz)), b.invR);
  b.v = I::mul(I::add(I::add(I::mul(M[3], b.dx), I::mul(M[4], b.dy)), I::mul(M[5], b.dz)), b.invR);
  b.ww = I::mul(I::add(I::add(I::mul(M[6], b.dx), I::mul(M[7], b.dy)), I::mul(M[8], b.dz)), b.invR);
  b.c = b.F + 13;
  b.u2 = I::mul(b.u, b.u), b.v2 = I::mul(b.v, b.v), b.uv = I::mul(b.u, b.v);
}

// The local function's value q (in units of R).
template <class I>
MPUMESH_SIMD_STEP typename I::V block_value(const LeafBlock<I>& b) {
  using V = typename I::V;
  const V* c = b.c;
  const V u = b.u, v = b.v, ww = b.ww, u2 = b.u2, v2 = b.v2, uv = b.uv;
  V q = c[0];
  q = I::add(q, I::mul(c[1], u));
  q = I::add(q, I::mul(c[2], v));
  q = I::add(q, I::mul(c[3], u2));
  q = I::add(q, I::mul(c[4], uv));
  q = I::add(q, I::mul(c[5], v2));
  q = I::add(q, I::mul(I::mul(c[6], u2), u));
  q = I::add(q, I::mul(I::mul(c[7], u2), v));
  q = I::add(q, I::mul(I::mul(c[8], u), v2));
  q = I::add(q, I::mul(I::mul(c[9], v2), v));
  q = I::add(q, I::mul(I::mul(c[10], u2), u2));
  q = I::add(q, I::mul(I::mul(c[11], u2), uv));
  q = I::add(q, I::mul(I::mul(c[12], u2), v2));
  q = I::add(q, I::mul(I::mul(c[13], uv), v2));
  q = I::add(q, I::mul(I::mul(c[14], v2), v2));
  q = I::add(q, I::mul(c[15], ww));
  q = I::add(q, I::mul(I::mul(c[16], ww), ww));
  q = I::add(q, I::mul(I::mul(c[17], u), ww));
  q = I::add(q, I::mul(I::mul(c[18], v), ww));
  q = I::add(q, I::mul(I::mul(c[19], u2), ww));
  q = I::add(q, I::mul(I::mul(c[20], uv), ww));
  q = I::add(q, I::mul(I::mul(c[21], v2), ww));
  return q;
}

// The local function's gradient in the leaf's frame (g[0..2] along u, v, w).
template <class I>
MPUMESH_SIMD_STEP void block_gradient(const LeafBlock<I>& b, typename I::V g[3]) {
  using V = typename I::V;
  const V* c = b.c;
  const V u = b.u, v = b.v, ww = b.ww, u2 = b.u2, v2 = b.v2, uv = b.uv;
  const V two = I::set1(2.0), three = I::set1(3.0), four = I::set1(4.0);
  V g0 = c[1];
  g0 = I::add(g0, I::mul(I::mul(two, c[3]), u));
  g0 = I::add(g0, I::mul(c[4], v));
  g0 = I::add(g0, I::mul(I::mul(three, c[6]), u2));
  g0 = I::add(g0, I::mul(I::mul(two, c[7]), uv));
  g0 = I::add(g0, I::mul(c[8], v2));
  g0 = I::add(g0, I::mul(I::mul(I::mul(four, c[10]), u2), u));
  g0 = I::add(g0, I::mul(I::mul(I::mul(three, c[11]), u2), v));
  g0 = I::add(g0, I::mul(I::mul(I::mul(two, c[12]), u), v2));
  g0 = I::add(g0, I::mul(I::mul(c[13], v2), v));
  g0 = I::add(g0, I::mul(c[17], ww));
  g0 = I::add(g0, I::mul(I::mul(I::mul(two, c[19]), u), ww));
  g0 = I::add(g0, I::mul(I::mul(c[20], v), ww));
  V g1 = c[2];
  g1 = I::add(g1, I::mul(c[4], u));
  g1 = I::add(g1, I::mul(I::mul(two, c[5]), v));
  g1 = I::add(g1, I::mul(c[7], u2));
  g1 = I::add(g1, I::mul(I::mul(two, c[8]), uv));
  g1 = I::add(g1, I::mul(I::mul(three, c[9]), v2));
  g1 = I::add(g1, I::mul(I::mul(c[11], u2), u));
  g1 = I::add(g1, I::mul(I::mul(I::mul(two, c[12]), u2), v));
  g1 = I::add(g1, I::mul(I::mul(I::mul(three, c[13]), u), v2));
  g1 = I::add(g1, I::mul(I::mul(I::mul(four, c[14]), v2), v));
  g1 = I::add(g1, I::mul(c[18], ww));
  g1 = I::add(g1, I::mul(I::mul(c[20], u), ww));
  g1 = I::add(g1, I::mul(I::mul(I::mul(two, c[21]), v), ww));
  V g2 = c[15];
  g2 = I::add(g2, I::mul(I::mul(two, c[16]), ww));
  g2 = I::add(g2, I::mul(c[17], u));
  g2 = I::add(g2, I::mul(c[18], v));
  g2 = I::add(g2, I::mul(c[19], u2));
  g2 = I::add(g2, I::mul(c[20], uv));
  g2 = I::add(g2, I::mul(c[21], v2));
  g[0] = g0, g[1] = g1, g[2] = g2;
}

// The local function's Hessian in the leaf's frame, symmetric: H[a][b].
template <class I>
MPUMESH_SIMD_STEP void block_hessian(const LeafBlock<I>& b, typename I::V H[3][3]) {
  using V = typename I::V;
  const V* c = b.c;
  const V u = b.u, v = b.v, ww = b.ww, u2 = b.u2, v2 = b.v2, uv = b.uv;
  const V two = I::set1(2.0), three = I::set1(3.0), four = I::set1(4.0), six = I::set1(6.0), twelve = I::set1(12.0);
  V h0 = I::mul(two, c[3]);
  h0 = I::add(h0, I::mul(I::mul(six, c[6]), u));
  h0 = I::add(h0, I::mul(I::mul(two, c[7]), v));
  h0 = I::add(h0, I::mul(I::mul(twelve, c[10]), u2));
  h0 = I::add(h0, I::mul(I::mul(six, c[11]), uv));
  h0 = I::add(h0, I::mul(I::mul(two, c[12]), v2));
  h0 = I::add(h0, I::mul(I::mul(two, c[19]), ww));
  V h1 = c[4];
  h1 = I::add(h1, I::mul(I::mul(two, c[7]), u));
  h1 = I::add(h1, I::mul(I::mul(two, c[8]), v));
  h1 = I::add(h1, I::mul(I::mul(three, c[11]), u2));
  h1 = I::add(h1, I::mul(I::mul(four, c[12]), uv));
  h1 = I::add(h1, I::mul(I::mul(three, c[13]), v2));
  h1 = I::add(h1, I::mul(c[20], ww));
  V h3 = I::mul(two, c[5]);
  h3 = I::add(h3, I::mul(I::mul(two, c[8]), u));
  h3 = I::add(h3, I::mul(I::mul(six, c[9]), v));
  h3 = I::add(h3, I::mul(I::mul(two, c[12]), u2));
  h3 = I::add(h3, I::mul(I::mul(six, c[13]), uv));
  h3 = I::add(h3, I::mul(I::mul(twelve, c[14]), v2));
  h3 = I::add(h3, I::mul(I::mul(two, c[21]), ww));
  V h2 = c[17];
  h2 = I::add(h2, I::mul(I::mul(two, c[19]), u));
  h2 = I::add(h2, I::mul(c[20], v));
  V h4 = c[18];
  h4 = I::add(h4, I::mul(c[20], u));
  h4 = I::add(h4, I::mul(I::mul(two, c[21]), v));
  const V h5 = I::mul(two, c[16]);
  H[0][0] = h0, H[0][1] = h1, H[0][2] = h2;
  H[1][0] = h1, H[1][1] = h3, H[1][2] = h4;
  H[2][0] = h2, H[2][1] = h4, H[2][2] = h5;
}

// The blended sums' derivative terms: the gradient's (kOrder >= 1), the leaves' own
// Hessians' (kOrder >= 2) and the Hessian of f's (kOrder >= 3).
template <class I, int kOrder>
MPUMESH_SIMD_STEP void add_derivatives(const LeafBlock<I>& b, typename I::V Qs, Sums<I>& s) {
  using V = typename I::V;
  using Mask = typename I::Mask;
  const V* M = b.M;
  V g[3];
  block_gradient(b, g);
  const V c15 = I::set1(1.5), c05 = I::set1(0.5), m2 = I::set1(-2.0);
  const V sc = I::mul(c15, b.invR);
  const Mask inner = I::le(I::mul(sc, b.r), c05);
  const V k1 = I::sel(inner, I::mul(I::mul(m2, sc), sc), I::div(b.dw, b.r));
  const V d[3] = {b.dx, b.dy, b.dz};
  V gw[3], gQ[3];
  for (int i = 0; i < 3; ++i) {
    gw[i] = I::mul(k1, d[i]);
    gQ[i] = I::add(I::add(I::mul(M[i], g[0]), I::mul(M[3 + i], g[1])), I::mul(M[6 + i], g[2]));
    s.gN[i] = I::add(s.gN[i], I::add(I::mul(Qs, gw[i]), I::mul(b.w, gQ[i])));
    s.gD[i] = I::add(s.gD[i], gw[i]);
  }
  if constexpr (kOrder >= 2) {
    V Hl[3][3];
    block_hessian(b, Hl);
    V A[3][3];
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k)
        A[a][k] = I::add(I::add(I::mul(Hl[a][0], M[k]), I::mul(Hl[a][1], M[3 + k])), I::mul(Hl[a][2], M[6 + k]));
    constexpr int kI[6] = {0, 0, 0, 1, 1, 2}, kJ[6] = {0, 1, 2, 1, 2, 2};
    V HQ[6];
    for (int e = 0; e < 6; ++e) {
      const int i = kI[e], k = kJ[e];
      HQ[e] = I::mul(I::add(I::add(I::mul(M[i], A[0][k]), I::mul(M[3 + i], A[1][k])), I::mul(M[6 + i], A[2][k])),
                     b.invR);
      s.HbN[e] = I::add(s.HbN[e], I::mul(b.w, HQ[e]));
    }
    if constexpr (kOrder >= 3) {
      const V k2 = I::sel(inner, I::zero(), I::div(I::sub(b.d2w, I::div(b.dw, b.r)), b.r2));
      for (int e = 0; e < 6; ++e) {
        const int i = kI[e], k = kJ[e];
        const V Hw = I::add(i == k ? k1 : I::zero(), I::mul(I::mul(k2, d[i]), d[k]));
        s.HN[e] = I::add(s.HN[e], I::add(I::add(I::add(I::mul(Qs, Hw), I::mul(gw[i], gQ[k])), I::mul(gQ[i], gw[k])),
                                          I::mul(b.w, HQ[e])));
        s.HD[e] = I::add(s.HD[e], Hw);
      }
    }
  }
}

// A block of leaves' terms at the point, added to the running sums (chunk_terms and
// chunk_sums of the reference). `pad_from`: lanes from it on are padding, 4 R away along
// x, as the reference pads; f0 is set from lane 0 when `first`.
template <class I, int kOrder>
MPUMESH_SIMD_STEP void leaf_block(const typename I::T* const* p, const double x[3], int pad_from, double pad_dx, bool first,
                                  double& f0, Sums<I>& s) {
  using V = typename I::V;
  LeafBlock<I> b;
  load_block(p, x, pad_from, pad_dx, b);
  block_weights(b);
  block_frame(b);
  const V Q = I::mul(b.R, block_value(b));
  if (first) f0 = I::first(Q);
  const V Qs = I::sub(Q, I::set1(f0));
  s.N = I::add(s.N, I::mul(b.w, Qs));
  s.D = I::add(s.D, b.w);
  if constexpr (kOrder >= 1) add_derivatives<I, kOrder>(b, Qs, s);
}

#undef MPUMESH_SIMD_STEP

template <class I, int kOrder>
MPUMESH_SIMD_TARGET EvalOut eval_kernel(const EvalView& view, const double x[3]) {
  EvalOut out;
  // The lookup cell, as the reference finds it (a division by the cell size).
  const double cell = view.box_size / double(view.dims[0]);
  int64_t c[3];
  for (int d = 0; d < 3; ++d) {
    c[d] = int64_t(std::floor((x[d] - view.box_min[d]) / cell));
    if (c[d] < 0 || c[d] >= int64_t(view.dims[d])) {
      out.f = view.box_size;
      return out;
    }
  }
  const uint64_t cid = uint64_t(c[0]) + uint64_t(view.dims[0]) * (uint64_t(c[1]) + uint64_t(view.dims[1]) * uint64_t(c[2]));
  const uint32_t k0 = view.offsets[cid], k1 = view.offsets[cid + 1];
  if (k1 - k0 > kMaxCandidates) {
    out.handled = false;
    return out;
  }
  uint32_t hid[kMaxCandidates + 16];
  int n = 0;
  {
    using S = typename I::Support;
    const typename S::V px = S::set1(x[0]), py = S::set1(x[1]), pz = S::set1(x[2]);
    for (uint32_t k = k0; k < k1; k += 8)
      n += S::support(view.spheres, view.leaf_ids + k, int(k1 - k < 8 ? k1 - k : 8), px, py, pz, hid + n);
  }
  if (n == 0) {
    out.f = view.box_size;
    return out;
  }
  // Every hit's record requested at once (a double record's 288 bytes span up to six
  // cache lines), so that the blocks' loads below overlap instead of each block waiting in
  // turn: 12-15% faster on the CT surface, where the leaves (68 MB) are read from L3 or
  // memory. (Prefetching the candidates' spheres as well made it slower: those are cached.)
  constexpr int kRecordBytes = 36 * int(sizeof(typename I::T));
  for (int j = 0; j < n; ++j) {
    const char* rec = reinterpret_cast<const char*>(I::record(view, hid[j]));
    for (int line = 0; 64 * line < kRecordBytes; ++line) __builtin_prefetch(rec + 64 * line);
    __builtin_prefetch(rec + kRecordBytes - 1);
  }
  // The reference pads its last chunk of 32 leaves to whole lanes with that chunk's
  // first leaf, 4 R away along x (zero weight, zero terms).
  constexpr int kLanes = I::kLanes;
  const int padded = (n + kLanes - 1) / kLanes * kLanes, first_of_chunk = (n - 1) / 32 * 32;
  for (int j = n; j < padded; ++j) hid[j] = hid[first_of_chunk];
  const double pad_dx = 4 * double(I::record(view, hid[first_of_chunk])[3]);
  Sums<I> s;
  s.N = s.D = I::zero();
  for (int i = 0; i < 3; ++i) s.gN[i] = s.gD[i] = I::zero();
  for (int e = 0; e < 6; ++e) s.HbN[e] = s.HN[e] = s.HD[e] = I::zero();
  double f0 = 0;
  for (int b = 0; b < padded; b += kLanes) {
    const typename I::T* p[kLanes];
    for (int l = 0; l < kLanes; ++l) p[l] = I::record(view, hid[b + l]);
    leaf_block<I, kOrder>(p, x, n - b, pad_dx, b == 0, f0, s);
  }
  out.leaves = n;
  const double D = lane_total<I>(s.D);
  if (!(D > 0)) {
    out.f = view.box_size;
    out.leaves = 0;
    return out;
  }
  const double fs = lane_total<I>(s.N) / D;
  out.f = f0 + fs;
  if constexpr (kOrder >= 1) {
    double gD[3];
    for (int i = 0; i < 3; ++i) {
      gD[i] = lane_total<I>(s.gD[i]);
      out.g[i] = (lane_total<I>(s.gN[i]) - fs * gD[i]) / D;
    }
    constexpr int kI[6] = {0, 0, 0, 1, 1, 2}, kJ[6] = {0, 1, 2, 1, 2, 2};
    for (int e = 0; e < 6; ++e) {
      const int i = kI[e], j = kJ[e];
      if constexpr (kOrder >= 2) out.Hb[e] = lane_total<I>(s.HbN[e]) / D;
      if constexpr (kOrder >= 3)
        out.H[e] = (lane_total<I>(s.HN[e]) - fs * lane_total<I>(s.HD[e]) - out.g[i] * gD[j] - gD[i] * out.g[j]) / D;
    }
  }
  return out;
}

template <class I>
MPUMESH_SIMD_TARGET EvalOut eval_dispatch(const EvalView& v, const double x[3], int order) {
  switch (order) {
    case 0: return eval_kernel<I, 0>(v, x);
    case 1: return eval_kernel<I, 1>(v, x);
    case 2: return eval_kernel<I, 2>(v, x);
    default: return eval_kernel<I, 3>(v, x);
  }
}

}  // namespace mpumesh::mpu::simd
