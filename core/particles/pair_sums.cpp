#include "particles/pair_sums.h"

#include <immintrin.h>

#include <cstring>

namespace mpumesh::particles {
namespace {

// exp_nonpositive's constants: log2(e); ln 2 in two parts (the high part has 20 trailing
// zero bits, so n times it is exact for |n| < 2^20); 1.5 · 2^52, which rounds a sum to
// an integer (to nearest) and holds that integer in its low bits.
constexpr double kLog2e = 1.4426950408889634, kLn2Hi = 6.93147180369123816490e-01,
                 kLn2Lo = 1.90821492927058770002e-10, kShift = 6755399441055744.0, kFloor = -700;
constexpr uint64_t kShiftBits = 0x4338000000000000ull;
// 1/13!, 1/12!, ..., 1/1!, 1/0!: Horner's order.
constexpr double kTaylor[14] = {1.0 / 6227020800.0, 1.0 / 479001600.0, 1.0 / 39916800.0, 1.0 / 3628800.0,
                                1.0 / 362880.0,     1.0 / 40320.0,     1.0 / 5040.0,      1.0 / 720.0,
                                1.0 / 120.0,        1.0 / 24.0,        1.0 / 6.0,         0.5,
                                1.0,                1.0};

// The generic code's lanes, and the fixed tree that adds them.
constexpr int kLanes = 8;
double add_lanes(const double* l) { return ((l[0] + l[4]) + (l[2] + l[6])) + ((l[1] + l[5]) + (l[3] + l[7])); }

PairTotals pair_sums_generic(const PairView& v, uint32_t i, const uint32_t* jj, uint32_t m) {
  const double qx = v.x[3 * size_t(i)], qy = v.x[3 * size_t(i) + 1], qz = v.x[3 * size_t(i) + 2];
  const double si = v.sigma[i], isi = v.inv_s2[i], c2si2 = v.c2 * si * si;
  double E[kLanes] = {}, dE[kLanes] = {}, Dx[kLanes] = {}, Dy[kLanes] = {}, Dz[kLanes] = {}, St[kLanes] = {};
  for (uint32_t t = 0; t < m; ++t) {
    const int l = int(t % kLanes);
    const size_t j = jj[t];
    const double rx = qx - v.x[3 * j], ry = qy - v.x[3 * j + 1], rz = qz - v.x[3 * j + 2];
    const double r2 = rx * rx + ry * ry + rz * rz;
    const double sj = v.sigma[j], isj = v.inv_s2[j];
    const double h = -0.5 * r2;
    const double eij = r2 < c2si2 ? v.mu * exp_nonpositive(h * isi) : 0.0;
    const double eji = r2 < v.c2 * sj * sj ? v.mu * exp_nonpositive(h * isj) : 0.0;
    E[l] += eij + eji;
    dE[l] += r2 * isi / si * eij;
    const double a = eij * isi + eji * isj;
    Dx[l] += rx * a;
    Dy[l] += ry * a;
    Dz[l] += rz * a;
    // -∂(r a)/∂r along r: the pair's radial stiffness (positive beyond r = σ).
    const double s = r2 * (eij * isi * isi + eji * isj * isj) - a;
    St[l] += s < 0.0 ? 0.0 : s;
  }
  PairTotals out;
  out.E = add_lanes(E);
  out.dE = add_lanes(dE);
  out.D[0] = add_lanes(Dx);
  out.D[1] = add_lanes(Dy);
  out.D[2] = add_lanes(Dz);
  out.stiff = add_lanes(St);
  return out;
}

#if MPUMESH_X86_SIMD

// (Only intrinsics and plain arithmetic below: no template is instantiated under these
// targets.)
__attribute__((target("avx512f,avx512vl,avx512dq"))) __m512d exp_avx512(__m512d x) {
  const __m512d floor = _mm512_set1_pd(kFloor), shift = _mm512_set1_pd(kShift);
  x = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(x, floor, _CMP_LT_OQ), x, floor);
  const __m512d t = _mm512_add_pd(_mm512_mul_pd(x, _mm512_set1_pd(kLog2e)), shift);
  const __m512d n = _mm512_sub_pd(t, shift);
  const __m512d r = _mm512_sub_pd(_mm512_sub_pd(x, _mm512_mul_pd(n, _mm512_set1_pd(kLn2Hi))),
                                  _mm512_mul_pd(n, _mm512_set1_pd(kLn2Lo)));
  __m512d p = _mm512_set1_pd(kTaylor[0]);
  for (int k = 1; k < 14; ++k) p = _mm512_add_pd(_mm512_mul_pd(p, r), _mm512_set1_pd(kTaylor[k]));
  const __m512i k = _mm512_sub_epi64(_mm512_castpd_si512(t), _mm512_set1_epi64(int64_t(kShiftBits)));
  const __m512i bits = _mm512_slli_epi64(_mm512_add_epi64(k, _mm512_set1_epi64(1023)), 52);
  return _mm512_mul_pd(p, _mm512_castsi512_pd(bits));
}

__attribute__((target("avx512f,avx512vl,avx512dq"))) double add_lanes_avx512(__m512d v) {
  const __m256d h = _mm256_add_pd(_mm512_castpd512_pd256(v), _mm512_extractf64x4_pd(v, 1));
  const __m128d g = _mm_add_pd(_mm256_castpd256_pd128(h), _mm256_extractf128_pd(h, 1));
  return _mm_cvtsd_f64(_mm_add_sd(g, _mm_unpackhi_pd(g, g)));
}

__attribute__((target("avx512f,avx512vl,avx512dq"))) PairTotals pair_sums_avx512(const PairView& v, uint32_t i,
                                                                                  const uint32_t* jj, uint32_t m) {
  const __m512d qx = _mm512_set1_pd(v.x[3 * size_t(i)]), qy = _mm512_set1_pd(v.x[3 * size_t(i) + 1]),
                qz = _mm512_set1_pd(v.x[3 * size_t(i) + 2]);
  const double si_s = v.sigma[i], isi_s = v.inv_s2[i];
  const __m512d si = _mm512_set1_pd(si_s), isi = _mm512_set1_pd(isi_s), c2si2 = _mm512_set1_pd(v.c2 * si_s * si_s);
  const __m512d mu = _mm512_set1_pd(v.mu), c2 = _mm512_set1_pd(v.c2), half = _mm512_set1_pd(-0.5);
  const __m512d zero = _mm512_setzero_pd();
  __m512d E = zero, dE = zero, Dx = zero, Dy = zero, Dz = zero, St = zero;
  for (uint32_t t = 0; t < m; t += kLanes) {
    const __mmask8 valid = m - t >= 8 ? __mmask8(0xff) : __mmask8((1u << (m - t)) - 1);
    const __m256i j = _mm256_maskz_loadu_epi32(valid, jj + t);
    const __m256i j3 = _mm256_add_epi32(_mm256_add_epi32(j, j), j);
    const __m512d xj = _mm512_mask_i32gather_pd(zero, valid, j3, v.x, 8);
    const __m512d yj = _mm512_mask_i32gather_pd(zero, valid, j3, v.x + 1, 8);
    const __m512d zj = _mm512_mask_i32gather_pd(zero, valid, j3, v.x + 2, 8);
    const __m512d sj = _mm512_mask_i32gather_pd(zero, valid, j, v.sigma, 8);
    const __m512d isj = _mm512_mask_i32gather_pd(zero, valid, j, v.inv_s2, 8);
    const __m512d rx = _mm512_sub_pd(qx, xj), ry = _mm512_sub_pd(qy, yj), rz = _mm512_sub_pd(qz, zj);
    const __m512d r2 =
        _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(rx, rx), _mm512_mul_pd(ry, ry)), _mm512_mul_pd(rz, rz));
    const __m512d h = _mm512_mul_pd(half, r2);
    const __mmask8 in_i = _mm512_cmp_pd_mask(r2, c2si2, _CMP_LT_OQ);
    const __mmask8 in_j = _mm512_cmp_pd_mask(r2, _mm512_mul_pd(_mm512_mul_pd(c2, sj), sj), _CMP_LT_OQ);
    const __m512d eij = _mm512_maskz_mul_pd(in_i, mu, exp_avx512(_mm512_mul_pd(h, isi)));
    const __m512d eji = _mm512_maskz_mul_pd(in_j, mu, exp_avx512(_mm512_mul_pd(h, isj)));
    E = _mm512_mask_add_pd(E, valid, E, _mm512_add_pd(eij, eji));
    dE = _mm512_mask_add_pd(dE, valid, dE, _mm512_mul_pd(_mm512_div_pd(_mm512_mul_pd(r2, isi), si), eij));
    const __m512d a = _mm512_add_pd(_mm512_mul_pd(eij, isi), _mm512_mul_pd(eji, isj));
    Dx = _mm512_mask_add_pd(Dx, valid, Dx, _mm512_mul_pd(rx, a));
    Dy = _mm512_mask_add_pd(Dy, valid, Dy, _mm512_mul_pd(ry, a));
    Dz = _mm512_mask_add_pd(Dz, valid, Dz, _mm512_mul_pd(rz, a));
    const __m512d w =
        _mm512_add_pd(_mm512_mul_pd(_mm512_mul_pd(eij, isi), isi), _mm512_mul_pd(_mm512_mul_pd(eji, isj), isj));
    const __m512d s = _mm512_sub_pd(_mm512_mul_pd(r2, w), a);
    const __m512d s0 = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(s, zero, _CMP_LT_OQ), s, zero);
    St = _mm512_mask_add_pd(St, valid, St, s0);
  }
  PairTotals out;
  out.E = add_lanes_avx512(E);
  out.dE = add_lanes_avx512(dE);
  out.D[0] = add_lanes_avx512(Dx);
  out.D[1] = add_lanes_avx512(Dy);
  out.D[2] = add_lanes_avx512(Dz);
  out.stiff = add_lanes_avx512(St);
  return out;
}

// Lanes 0-3 of the eight in one register, lanes 4-7 in another.
__attribute__((target("avx2"))) __m256d exp_avx2(__m256d x) {
  const __m256d floor = _mm256_set1_pd(kFloor), shift = _mm256_set1_pd(kShift);
  x = _mm256_blendv_pd(x, floor, _mm256_cmp_pd(x, floor, _CMP_LT_OQ));
  const __m256d t = _mm256_add_pd(_mm256_mul_pd(x, _mm256_set1_pd(kLog2e)), shift);
  const __m256d n = _mm256_sub_pd(t, shift);
  const __m256d r = _mm256_sub_pd(_mm256_sub_pd(x, _mm256_mul_pd(n, _mm256_set1_pd(kLn2Hi))),
                                  _mm256_mul_pd(n, _mm256_set1_pd(kLn2Lo)));
  __m256d p = _mm256_set1_pd(kTaylor[0]);
  for (int k = 1; k < 14; ++k) p = _mm256_add_pd(_mm256_mul_pd(p, r), _mm256_set1_pd(kTaylor[k]));
  const __m256i k = _mm256_sub_epi64(_mm256_castpd_si256(t), _mm256_set1_epi64x(int64_t(kShiftBits)));
  const __m256i bits = _mm256_slli_epi64(_mm256_add_epi64(k, _mm256_set1_epi64x(1023)), 52);
  return _mm256_mul_pd(p, _mm256_castsi256_pd(bits));
}

struct Avx2Sums {
  __m256d E, dE, Dx, Dy, Dz, St;
};

// Four pairs (indices j, all valid memory) into the sums of their lanes where `valid`.
__attribute__((target("avx2"))) void add_four_avx2(const PairView& v, const __m256d* q, __m256d si, __m256d isi,
                                                   __m256d c2si2, __m128i j, __m256d valid, Avx2Sums& s) {
  const __m256d zero = _mm256_setzero_pd();
  const __m128i j3 = _mm_add_epi32(_mm_add_epi32(j, j), j);
  const __m256d xj = _mm256_i32gather_pd(v.x, j3, 8), yj = _mm256_i32gather_pd(v.x + 1, j3, 8);
  const __m256d zj = _mm256_i32gather_pd(v.x + 2, j3, 8);
  const __m256d sj = _mm256_i32gather_pd(v.sigma, j, 8), isj = _mm256_i32gather_pd(v.inv_s2, j, 8);
  const __m256d rx = _mm256_sub_pd(q[0], xj), ry = _mm256_sub_pd(q[1], yj), rz = _mm256_sub_pd(q[2], zj);
  const __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(rx, rx), _mm256_mul_pd(ry, ry)), _mm256_mul_pd(rz, rz));
  const __m256d h = _mm256_mul_pd(_mm256_set1_pd(-0.5), r2);
  const __m256d mu = _mm256_set1_pd(v.mu), c2 = _mm256_set1_pd(v.c2);
  const __m256d in_i = _mm256_cmp_pd(r2, c2si2, _CMP_LT_OQ);
  const __m256d in_j = _mm256_cmp_pd(r2, _mm256_mul_pd(_mm256_mul_pd(c2, sj), sj), _CMP_LT_OQ);
  const __m256d eij = _mm256_and_pd(in_i, _mm256_mul_pd(mu, exp_avx2(_mm256_mul_pd(h, isi))));
  const __m256d eji = _mm256_and_pd(in_j, _mm256_mul_pd(mu, exp_avx2(_mm256_mul_pd(h, isj))));
  // Each sum gains its term only in the valid lanes.
  s.E = _mm256_blendv_pd(s.E, _mm256_add_pd(s.E, _mm256_add_pd(eij, eji)), valid);
  const __m256d de = _mm256_mul_pd(_mm256_div_pd(_mm256_mul_pd(r2, isi), si), eij);
  s.dE = _mm256_blendv_pd(s.dE, _mm256_add_pd(s.dE, de), valid);
  const __m256d a = _mm256_add_pd(_mm256_mul_pd(eij, isi), _mm256_mul_pd(eji, isj));
  s.Dx = _mm256_blendv_pd(s.Dx, _mm256_add_pd(s.Dx, _mm256_mul_pd(rx, a)), valid);
  s.Dy = _mm256_blendv_pd(s.Dy, _mm256_add_pd(s.Dy, _mm256_mul_pd(ry, a)), valid);
  s.Dz = _mm256_blendv_pd(s.Dz, _mm256_add_pd(s.Dz, _mm256_mul_pd(rz, a)), valid);
  const __m256d w =
      _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(eij, isi), isi), _mm256_mul_pd(_mm256_mul_pd(eji, isj), isj));
  const __m256d st = _mm256_sub_pd(_mm256_mul_pd(r2, w), a);
  const __m256d st0 = _mm256_blendv_pd(st, zero, _mm256_cmp_pd(st, zero, _CMP_LT_OQ));
  s.St = _mm256_blendv_pd(s.St, _mm256_add_pd(s.St, st0), valid);
}

// The lanes of a (0-3) and b (4-7) in add_lanes' tree.
__attribute__((target("avx2"))) double add_lanes_avx2(__m256d a, __m256d b) {
  const __m256d h = _mm256_add_pd(a, b);
  const __m128d g = _mm_add_pd(_mm256_castpd256_pd128(h), _mm256_extractf128_pd(h, 1));
  return _mm_cvtsd_f64(_mm_add_sd(g, _mm_unpackhi_pd(g, g)));
}

__attribute__((target("avx2"))) PairTotals pair_sums_avx2(const PairView& v, uint32_t i, const uint32_t* jj,
                                                          uint32_t m) {
  const __m256d q[3] = {_mm256_set1_pd(v.x[3 * size_t(i)]), _mm256_set1_pd(v.x[3 * size_t(i) + 1]),
                        _mm256_set1_pd(v.x[3 * size_t(i) + 2])};
  const double si_s = v.sigma[i], isi_s = v.inv_s2[i];
  const __m256d si = _mm256_set1_pd(si_s), isi = _mm256_set1_pd(isi_s), c2si2 = _mm256_set1_pd(v.c2 * si_s * si_s);
  const __m256d zero = _mm256_setzero_pd();
  Avx2Sums lo = {zero, zero, zero, zero, zero, zero}, hi = lo;
  const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
  for (uint32_t t = 0; t < m; t += kLanes) {
    // The last eight padded with i itself (valid memory), its lanes left out.
    uint32_t idx[kLanes];
    for (uint32_t k = 0; k < uint32_t(kLanes); ++k) idx[k] = t + k < m ? jj[t + k] : i;
    const __m256i left = _mm256_set1_epi64x(int64_t(m - t));
    const __m256d valid_lo = _mm256_castsi256_pd(_mm256_cmpgt_epi64(left, lane));
    const __m256i lane_hi = _mm256_add_epi64(lane, _mm256_set1_epi64x(4));
    const __m256d valid_hi = _mm256_castsi256_pd(_mm256_cmpgt_epi64(left, lane_hi));
    add_four_avx2(v, q, si, isi, c2si2, _mm_loadu_si128(reinterpret_cast<const __m128i*>(idx)), valid_lo, lo);
    add_four_avx2(v, q, si, isi, c2si2, _mm_loadu_si128(reinterpret_cast<const __m128i*>(idx + 4)), valid_hi, hi);
  }
  PairTotals out;
  out.E = add_lanes_avx2(lo.E, hi.E);
  out.dE = add_lanes_avx2(lo.dE, hi.dE);
  out.D[0] = add_lanes_avx2(lo.Dx, hi.Dx);
  out.D[1] = add_lanes_avx2(lo.Dy, hi.Dy);
  out.D[2] = add_lanes_avx2(lo.Dz, hi.Dz);
  out.stiff = add_lanes_avx2(lo.St, hi.St);
  return out;
}

#endif

}  // namespace

double exp_nonpositive(double x) {
  if (x < kFloor) x = kFloor;
  const double t = x * kLog2e + kShift;
  const double n = t - kShift;
  const double r = (x - n * kLn2Hi) - n * kLn2Lo;
  double p = kTaylor[0];
  for (int k = 1; k < 14; ++k) p = p * r + kTaylor[k];
  uint64_t tb;
  std::memcpy(&tb, &t, sizeof tb);
  const uint64_t bits = (tb - kShiftBits + 1023) << 52;  // 2^n (unsigned: NaN wraps harmlessly)
  double scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

PairTotals pair_sums(const PairView& v, uint32_t i, const uint32_t* j, uint32_t m, SimdLevel level) {
#if MPUMESH_X86_SIMD
  if (level == SimdLevel::kAvx512) return pair_sums_avx512(v, i, j, m);
  if (level == SimdLevel::kAvx2) return pair_sums_avx2(v, i, j, m);
#endif
  (void)level;
  return pair_sums_generic(v, i, j, m);
}

}  // namespace mpumesh::particles
