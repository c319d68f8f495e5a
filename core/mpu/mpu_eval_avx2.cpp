// The AVX2 path of the MPU evaluation (mpu_eval_simd.h): a vector of 8 doubles is two
// 4-double registers, the support test's hits are compacted through a table of lane
// permutations, and four leaves at a time are transposed 4 x 4 in registers.
#include <immintrin.h>

#include <cstdint>

#include "common/simd_level.h"
#include "mpu/mpu_eval_simd.h"

#if MPUMESH_X86_SIMD

#define MPUMESH_SIMD_TARGET __attribute__((target("avx2")))

namespace mpumesh::mpu::simd {
namespace {

// For each 8-bit hit mask, the lanes that hit, in order (then zeros), one byte each. (A
// plain array: no standard-library template is instantiated in this file.)
struct CompressTable {
  uint64_t lanes[256];
};
constexpr CompressTable make_compress_table() {
  CompressTable t{};
  for (int m = 0; m < 256; ++m) {
    uint64_t packed = 0;
    int n = 0;
    for (int l = 0; l < 8; ++l)
      if (m >> l & 1) packed |= uint64_t(l) << (8 * n++);
    t.lanes[m] = packed;
  }
  return t;
}
constexpr CompressTable kCompress = make_compress_table();

struct Avx2 {
  struct V {
    __m256d a, b;  // lanes 0-3, 4-7
  };
  using Mask = V;  // all ones where set
  MPUMESH_SIMD_TARGET static V set1(double x) { return {_mm256_set1_pd(x), _mm256_set1_pd(x)}; }
  MPUMESH_SIMD_TARGET static V zero() { return {_mm256_setzero_pd(), _mm256_setzero_pd()}; }
  MPUMESH_SIMD_TARGET static V add(V x, V y) { return {_mm256_add_pd(x.a, y.a), _mm256_add_pd(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V sub(V x, V y) { return {_mm256_sub_pd(x.a, y.a), _mm256_sub_pd(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V mul(V x, V y) { return {_mm256_mul_pd(x.a, y.a), _mm256_mul_pd(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V div(V x, V y) { return {_mm256_div_pd(x.a, y.a), _mm256_div_pd(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V sqrt(V x) { return {_mm256_sqrt_pd(x.a), _mm256_sqrt_pd(x.b)}; }
  MPUMESH_SIMD_TARGET static Mask lt(V x, V y) {
    return {_mm256_cmp_pd(x.a, y.a, _CMP_LT_OQ), _mm256_cmp_pd(x.b, y.b, _CMP_LT_OQ)};
  }
  MPUMESH_SIMD_TARGET static Mask le(V x, V y) {
    return {_mm256_cmp_pd(x.a, y.a, _CMP_LE_OQ), _mm256_cmp_pd(x.b, y.b, _CMP_LE_OQ)};
  }
  MPUMESH_SIMD_TARGET static V sel(Mask m, V t, V f) {
    return {_mm256_blendv_pd(f.a, t.a, m.a), _mm256_blendv_pd(f.b, t.b, m.b)};
  }
  MPUMESH_SIMD_TARGET static V keep(Mask m, V x) { return {_mm256_and_pd(m.a, x.a), _mm256_and_pd(m.b, x.b)}; }
  MPUMESH_SIMD_TARGET static double first(V x) { return _mm256_cvtsd_f64(x.a); }
  MPUMESH_SIMD_TARGET static void store(double* p, V x) {
    _mm256_storeu_pd(p, x.a);
    _mm256_storeu_pd(p + 4, x.b);
  }
  MPUMESH_SIMD_TARGET static Mask lanes_from(int k) {
    const __m256i lane_lo = _mm256_setr_epi64x(0, 1, 2, 3), lane_hi = _mm256_setr_epi64x(4, 5, 6, 7);
    const __m256i kk = _mm256_set1_epi64x(k - 1);
    return {_mm256_castsi256_pd(_mm256_cmpgt_epi64(lane_lo, kk)), _mm256_castsi256_pd(_mm256_cmpgt_epi64(lane_hi, kk))};
  }

  // c[j] lane i = r[i][j], 4 x 4.
  MPUMESH_SIMD_TARGET static void transpose4(__m256d r0, __m256d r1, __m256d r2, __m256d r3, __m256d* c0, __m256d* c1,
                                             __m256d* c2, __m256d* c3) {
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    *c0 = _mm256_permute2f128_pd(t0, t2, 0x20);
    *c1 = _mm256_permute2f128_pd(t1, t3, 0x20);
    *c2 = _mm256_permute2f128_pd(t0, t2, 0x31);
    *c3 = _mm256_permute2f128_pd(t1, t3, 0x31);
  }

  MPUMESH_SIMD_TARGET static void load_leaves(const double* const* p, V* F) {
    for (int blk = 0; blk < 9; ++blk) {
      const int o = 4 * blk;
      transpose4(_mm256_loadu_pd(p[0] + o), _mm256_loadu_pd(p[1] + o), _mm256_loadu_pd(p[2] + o),
                 _mm256_loadu_pd(p[3] + o), &F[o].a, &F[o + 1].a, &F[o + 2].a, &F[o + 3].a);
      transpose4(_mm256_loadu_pd(p[4] + o), _mm256_loadu_pd(p[5] + o), _mm256_loadu_pd(p[6] + o),
                 _mm256_loadu_pd(p[7] + o), &F[o].b, &F[o + 1].b, &F[o + 2].b, &F[o + 3].b);
    }
  }

  MPUMESH_SIMD_TARGET static int support(const double* spheres, const uint32_t* ids, int count, V px, V py, V pz,
                                         uint32_t* out) {
    uint32_t tail[8];
    if (count < 8) {  // a cell's last few: the rest of the lanes test the first again
      for (int l = 0; l < 8; ++l) tail[l] = ids[l < count ? l : 0];
      ids = tail;
    }
    const uint32_t* id = ids;
    V cx, cy, cz, R2;
    transpose4(_mm256_loadu_pd(spheres + 4 * size_t(id[0])), _mm256_loadu_pd(spheres + 4 * size_t(id[1])),
               _mm256_loadu_pd(spheres + 4 * size_t(id[2])), _mm256_loadu_pd(spheres + 4 * size_t(id[3])), &cx.a, &cy.a,
               &cz.a, &R2.a);
    transpose4(_mm256_loadu_pd(spheres + 4 * size_t(id[4])), _mm256_loadu_pd(spheres + 4 * size_t(id[5])),
               _mm256_loadu_pd(spheres + 4 * size_t(id[6])), _mm256_loadu_pd(spheres + 4 * size_t(id[7])), &cx.b, &cy.b,
               &cz.b, &R2.b);
    const V dx = sub(px, cx), dy = sub(py, cy), dz = sub(pz, cz);
    const V r2 = add(add(mul(dx, dx), mul(dy, dy)), mul(dz, dz));
    const Mask hit = lt(r2, R2);
    const unsigned m = (unsigned(_mm256_movemask_pd(hit.a)) | unsigned(_mm256_movemask_pd(hit.b)) << 4) &
                       ((1u << count) - 1);
    const __m256i perm = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(int64_t(kCompress.lanes[m])));
    const __m256i idv = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(id));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_permutevar8x32_epi32(idv, perm));
    return __builtin_popcount(m);
  }
};

}  // namespace
}  // namespace mpumesh::mpu::simd

#include "mpu/mpu_eval_simd_kernel.h"

namespace mpumesh::mpu::simd {

MPUMESH_SIMD_TARGET EvalOut evaluate_avx2(const EvalView& v, const double x[3], int order) {
  return eval_dispatch<Avx2>(v, x, order);
}

}  // namespace mpumesh::mpu::simd

#endif  // x86-64 (elsewhere mpu_eval_simd.cpp defines the entry point)
