#include "particles/pair_filter.h"

#include <immintrin.h>

#include <algorithm>

namespace mpumesh::particles {
namespace {

// The reference: the test as repulsion_step writes it.
uint32_t within_generic(const double* x, const double* y, const double* z, const double* sg, uint32_t k0,
                        uint32_t k1, const double* q, double s2, double c2, uint32_t* out) {
  uint32_t n = 0;
  for (uint32_t k = k0; k < k1; ++k) {
    const double rx = q[0] - x[k], ry = q[1] - y[k], rz = q[2] - z[k];
    const double r2 = rx * rx + ry * ry + rz * rz;
    out[n] = k;
    n += !(r2 >= c2 * std::max(s2, sg[k] * sg[k]));
  }
  return n;
}

#if MPUMESH_X86_SIMD

// (Only intrinsics and plain arithmetic below: no template is instantiated under these
// targets.) std::max(s2, σ²) is σ² where s2 < σ², else s2: a compare and a blend, not
// maxpd, whose answer for NaN differs.
__attribute__((target("avx512f,avx512vl"))) uint32_t within_avx512(const double* x, const double* y, const double* z,
                                                                     const double* sg, uint32_t k0, uint32_t k1,
                                                                     const double* q, double s2, double c2,
                                                                     uint32_t* out) {
  const __m512d qx = _mm512_set1_pd(q[0]), qy = _mm512_set1_pd(q[1]), qz = _mm512_set1_pd(q[2]);
  const __m512d vs2 = _mm512_set1_pd(s2), vc2 = _mm512_set1_pd(c2);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  uint32_t n = 0;
  for (uint32_t k = k0; k < k1; k += 8) {
    const __mmask8 valid = k1 - k >= 8 ? __mmask8(0xff) : __mmask8((1u << (k1 - k)) - 1);
    const __m512d vx = _mm512_maskz_loadu_pd(valid, x + k), vy = _mm512_maskz_loadu_pd(valid, y + k);
    const __m512d vz = _mm512_maskz_loadu_pd(valid, z + k), vsg = _mm512_maskz_loadu_pd(valid, sg + k);
    const __m512d rx = _mm512_sub_pd(qx, vx), ry = _mm512_sub_pd(qy, vy), rz = _mm512_sub_pd(qz, vz);
    const __m512d r2 = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(rx, rx), _mm512_mul_pd(ry, ry)), _mm512_mul_pd(rz, rz));
    const __m512d sj2 = _mm512_mul_pd(vsg, vsg);
    const __m512d big = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(vs2, sj2, _CMP_LT_OQ), vs2, sj2);
    const __mmask8 keep = _mm512_mask_cmp_pd_mask(valid, r2, _mm512_mul_pd(vc2, big), _CMP_NGE_UQ);
    const __m256i idx = _mm256_add_epi32(_mm256_set1_epi32(int(k)), lane);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + n), _mm256_maskz_compress_epi32(keep, idx));
    n += uint32_t(__builtin_popcount(keep));
  }
  return n;
}

// For each 4-bit mask, the lanes that pass, in order, two bits each.
constexpr int kLanes4[16] = {0, 0, 1, 4, 2, 8, 9, 36, 3, 12, 13, 52, 14, 56, 57, 228};

__attribute__((target("avx2"))) uint32_t within_avx2(const double* x, const double* y, const double* z, const double* sg,
                                                     uint32_t k0, uint32_t k1, const double* q, double s2, double c2,
                                                     uint32_t* out) {
  const __m256d qx = _mm256_set1_pd(q[0]), qy = _mm256_set1_pd(q[1]), qz = _mm256_set1_pd(q[2]);
  const __m256d vs2 = _mm256_set1_pd(s2), vc2 = _mm256_set1_pd(c2);
  uint32_t n = 0, k = k0;
  for (; k + 4 <= k1; k += 4) {
    const __m256d rx = _mm256_sub_pd(qx, _mm256_loadu_pd(x + k)), ry = _mm256_sub_pd(qy, _mm256_loadu_pd(y + k));
    const __m256d rz = _mm256_sub_pd(qz, _mm256_loadu_pd(z + k)), vsg = _mm256_loadu_pd(sg + k);
    const __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(rx, rx), _mm256_mul_pd(ry, ry)), _mm256_mul_pd(rz, rz));
    const __m256d sj2 = _mm256_mul_pd(vsg, vsg);
    const __m256d big = _mm256_blendv_pd(vs2, sj2, _mm256_cmp_pd(vs2, sj2, _CMP_LT_OQ));
    const int keep = _mm256_movemask_pd(_mm256_cmp_pd(r2, _mm256_mul_pd(vc2, big), _CMP_NGE_UQ));
    const int lanes = kLanes4[keep];
    for (int t = 0, c = __builtin_popcount(unsigned(keep)); t < c; ++t) out[n + uint32_t(t)] = k + uint32_t(lanes >> (2 * t) & 3);
    n += uint32_t(__builtin_popcount(unsigned(keep)));
  }
  return n + within_generic(x, y, z, sg, k, k1, q, s2, c2, out + n);
}

#endif

}  // namespace

uint32_t pairs_within(const CandidateSoa& a, uint32_t k0, uint32_t k1, const double q[3], double s2, double c2,
                      uint32_t* out, SimdLevel level) {
  const double *x = a.x.data(), *y = a.y.data(), *z = a.z.data(), *sg = a.sigma.data();
#if MPUMESH_X86_SIMD
  if (level == SimdLevel::kAvx512) return within_avx512(x, y, z, sg, k0, k1, q, s2, c2, out);
  if (level == SimdLevel::kAvx2) return within_avx2(x, y, z, sg, k0, k1, q, s2, c2, out);
#endif
  return within_generic(x, y, z, sg, k0, k1, q, s2, c2, out);
}

}  // namespace mpumesh::particles
