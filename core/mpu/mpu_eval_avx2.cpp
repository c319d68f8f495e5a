// The AVX2 path of the MPU evaluation (mpu_eval_simd.h): a vector of 8 doubles is two
// 4-double registers, the support test's hits are compacted through a table of lane
// permutations, and four leaves at a time are transposed 4 x 4 in registers; in single
// precision 16 floats are two 8-float registers, eight leaves transposed 8 x 8.
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
  using T = double;
  static constexpr int kLanes = 8;
  using Support = Avx2;
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
  MPUMESH_SIMD_TARGET static const double* record(const EvalView& v, uint32_t id) {
    return v.leaves + size_t(id) * v.leaf_stride;
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


// The single-precision kernel's vectors: 16 floats as two 8-float registers; its
// support test is the double one's above.
struct Avx2F {
  using T = float;
  static constexpr int kLanes = 16;
  using Support = Avx2;
  struct V {
    __m256 a, b;  // lanes 0-7, 8-15
  };
  using Mask = V;  // all ones where set
  MPUMESH_SIMD_TARGET static V set1(double x) { return {_mm256_set1_ps(float(x)), _mm256_set1_ps(float(x))}; }
  MPUMESH_SIMD_TARGET static V zero() { return {_mm256_setzero_ps(), _mm256_setzero_ps()}; }
  MPUMESH_SIMD_TARGET static V add(V x, V y) { return {_mm256_add_ps(x.a, y.a), _mm256_add_ps(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V sub(V x, V y) { return {_mm256_sub_ps(x.a, y.a), _mm256_sub_ps(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V mul(V x, V y) { return {_mm256_mul_ps(x.a, y.a), _mm256_mul_ps(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V div(V x, V y) { return {_mm256_div_ps(x.a, y.a), _mm256_div_ps(x.b, y.b)}; }
  MPUMESH_SIMD_TARGET static V sqrt(V x) { return {_mm256_sqrt_ps(x.a), _mm256_sqrt_ps(x.b)}; }
  MPUMESH_SIMD_TARGET static Mask lt(V x, V y) {
    return {_mm256_cmp_ps(x.a, y.a, _CMP_LT_OQ), _mm256_cmp_ps(x.b, y.b, _CMP_LT_OQ)};
  }
  MPUMESH_SIMD_TARGET static Mask le(V x, V y) {
    return {_mm256_cmp_ps(x.a, y.a, _CMP_LE_OQ), _mm256_cmp_ps(x.b, y.b, _CMP_LE_OQ)};
  }
  MPUMESH_SIMD_TARGET static V sel(Mask m, V t, V f) {
    return {_mm256_blendv_ps(f.a, t.a, m.a), _mm256_blendv_ps(f.b, t.b, m.b)};
  }
  MPUMESH_SIMD_TARGET static V keep(Mask m, V x) { return {_mm256_and_ps(m.a, x.a), _mm256_and_ps(m.b, x.b)}; }
  MPUMESH_SIMD_TARGET static float first(V x) { return _mm256_cvtss_f32(x.a); }
  MPUMESH_SIMD_TARGET static void store(float* p, V x) {
    _mm256_storeu_ps(p, x.a);
    _mm256_storeu_ps(p + 8, x.b);
  }
  MPUMESH_SIMD_TARGET static Mask lanes_from(int k) {
    const __m256i lane_lo = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
                  lane_hi = _mm256_setr_epi32(8, 9, 10, 11, 12, 13, 14, 15);
    const __m256i kk = _mm256_set1_epi32(k - 1);
    return {_mm256_castsi256_ps(_mm256_cmpgt_epi32(lane_lo, kk)), _mm256_castsi256_ps(_mm256_cmpgt_epi32(lane_hi, kk))};
  }
  MPUMESH_SIMD_TARGET static const float* record(const EvalView& v, uint32_t id) {
    return v.records32 + size_t(id) * 36;
  }

  // c[j] lane i = number o + j of leaf p[i], 8 x 8: pairs, 4 x 4 blocks within 128-bit
  // lanes, then the halves.
  MPUMESH_SIMD_TARGET static void transpose8(const float* const* p, int o, __m256* c) {
    __m256 t[8], u[8];
    for (int i = 0; i < 4; ++i) {
      const __m256 r0 = _mm256_loadu_ps(p[2 * i] + o), r1 = _mm256_loadu_ps(p[2 * i + 1] + o);
      t[2 * i] = _mm256_unpacklo_ps(r0, r1);
      t[2 * i + 1] = _mm256_unpackhi_ps(r0, r1);
    }
    for (int i = 0; i < 2; ++i) {
      u[4 * i + 0] = _mm256_shuffle_ps(t[4 * i + 0], t[4 * i + 2], 0x44);
      u[4 * i + 1] = _mm256_shuffle_ps(t[4 * i + 0], t[4 * i + 2], 0xEE);
      u[4 * i + 2] = _mm256_shuffle_ps(t[4 * i + 1], t[4 * i + 3], 0x44);
      u[4 * i + 3] = _mm256_shuffle_ps(t[4 * i + 1], t[4 * i + 3], 0xEE);
    }
    for (int k = 0; k < 4; ++k) {
      c[k] = _mm256_permute2f128_ps(u[k], u[4 + k], 0x20);
      c[4 + k] = _mm256_permute2f128_ps(u[k], u[4 + k], 0x31);
    }
  }

  // c[j] lane i = number 32 + j of leaf p[i], 8 x 4: two 4 x 4 transposes, joined.
  MPUMESH_SIMD_TARGET static void transpose8x4(const float* const* p, __m256* c) {
    __m128 lo[4], hi[4];
    for (int i = 0; i < 4; ++i) lo[i] = _mm_loadu_ps(p[i] + 32), hi[i] = _mm_loadu_ps(p[4 + i] + 32);
    _MM_TRANSPOSE4_PS(lo[0], lo[1], lo[2], lo[3]);
    _MM_TRANSPOSE4_PS(hi[0], hi[1], hi[2], hi[3]);
    for (int j = 0; j < 4; ++j) c[j] = _mm256_insertf128_ps(_mm256_castps128_ps256(lo[j]), hi[j], 1);
  }

  MPUMESH_SIMD_TARGET static void load_leaves(const float* const* p, V* F) {
    __m256 c[8];
    for (int half = 0; half < 2; ++half) {
      const float* const* q = p + 8 * half;
      for (int blk = 0; blk < 4; ++blk) {
        transpose8(q, 8 * blk, c);
        for (int j = 0; j < 8; ++j) (half ? F[8 * blk + j].b : F[8 * blk + j].a) = c[j];
      }
      transpose8x4(q, c);
      for (int j = 0; j < 4; ++j) (half ? F[32 + j].b : F[32 + j].a) = c[j];
    }
  }
};

}  // namespace
}  // namespace mpumesh::mpu::simd

#include "mpu/mpu_eval_simd_kernel.h"

namespace mpumesh::mpu::simd {

MPUMESH_SIMD_TARGET EvalOut evaluate_avx2(const EvalView& v, const double x[3], int order) {
  return eval_dispatch<Avx2>(v, x, order);
}

MPUMESH_SIMD_TARGET EvalOut evaluate_f32_avx2(const EvalView& v, const double x[3], int order) {
  return eval_dispatch<Avx2F>(v, x, order);
}

}  // namespace mpumesh::mpu::simd

#endif  // x86-64 (elsewhere mpu_eval_simd.cpp defines the entry point)
