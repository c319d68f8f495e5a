// The AVX-512 paths of the MPU evaluation (mpu_eval_simd.h): 8 doubles per register, the
// support test's hits compacted with vpcompressd, eight leaves transposed in registers;
// and in single precision 16 floats per register, sixteen leaves transposed.
#include <immintrin.h>

#include <cstdint>

#include "common/simd_level.h"
#include "mpu/mpu_eval_simd.h"

#if MPUMESH_X86_SIMD

#define MPUMESH_SIMD_TARGET __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw")))

namespace mpumesh::mpu::simd {
namespace {

struct Avx512 {
  using T = double;
  static constexpr int kLanes = 8;
  using Support = Avx512;
  using V = __m512d;
  using Mask = __mmask8;
  MPUMESH_SIMD_TARGET static V set1(double a) { return _mm512_set1_pd(a); }
  MPUMESH_SIMD_TARGET static V zero() { return _mm512_setzero_pd(); }
  MPUMESH_SIMD_TARGET static V add(V a, V b) { return _mm512_add_pd(a, b); }
  MPUMESH_SIMD_TARGET static V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  MPUMESH_SIMD_TARGET static V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  MPUMESH_SIMD_TARGET static V div(V a, V b) { return _mm512_div_pd(a, b); }
  MPUMESH_SIMD_TARGET static V sqrt(V a) { return _mm512_sqrt_pd(a); }
  MPUMESH_SIMD_TARGET static Mask lt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
  MPUMESH_SIMD_TARGET static Mask le(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
  MPUMESH_SIMD_TARGET static V sel(Mask m, V t, V f) { return _mm512_mask_blend_pd(m, f, t); }
  MPUMESH_SIMD_TARGET static V keep(Mask m, V a) { return _mm512_maskz_mov_pd(m, a); }
  MPUMESH_SIMD_TARGET static double first(V a) { return _mm512_cvtsd_f64(a); }
  MPUMESH_SIMD_TARGET static void store(double* p, V a) { _mm512_storeu_pd(p, a); }
  MPUMESH_SIMD_TARGET static Mask lanes_from(int k) { return Mask(0xffu << k); }
  MPUMESH_SIMD_TARGET static const double* record(const EvalView& v, uint32_t id) {
    return v.leaves + size_t(id) * v.leaf_stride;
  }

  // An 8 x 8 transpose in three rounds of shuffles.
  MPUMESH_SIMD_TARGET static void transpose(const V r[8], V* c) {
    V t[8], u[8];
    for (int i = 0; i < 4; ++i) {
      t[2 * i] = _mm512_unpacklo_pd(r[2 * i], r[2 * i + 1]);
      t[2 * i + 1] = _mm512_unpackhi_pd(r[2 * i], r[2 * i + 1]);
    }
    for (int h = 0; h < 2; ++h) {
      u[4 * h + 0] = _mm512_shuffle_f64x2(t[4 * h + 0], t[4 * h + 2], _MM_SHUFFLE(2, 0, 2, 0));
      u[4 * h + 1] = _mm512_shuffle_f64x2(t[4 * h + 0], t[4 * h + 2], _MM_SHUFFLE(3, 1, 3, 1));
      u[4 * h + 2] = _mm512_shuffle_f64x2(t[4 * h + 1], t[4 * h + 3], _MM_SHUFFLE(2, 0, 2, 0));
      u[4 * h + 3] = _mm512_shuffle_f64x2(t[4 * h + 1], t[4 * h + 3], _MM_SHUFFLE(3, 1, 3, 1));
    }
    c[0] = _mm512_shuffle_f64x2(u[0], u[4], _MM_SHUFFLE(2, 0, 2, 0));
    c[4] = _mm512_shuffle_f64x2(u[0], u[4], _MM_SHUFFLE(3, 1, 3, 1));
    c[2] = _mm512_shuffle_f64x2(u[1], u[5], _MM_SHUFFLE(2, 0, 2, 0));
    c[6] = _mm512_shuffle_f64x2(u[1], u[5], _MM_SHUFFLE(3, 1, 3, 1));
    c[1] = _mm512_shuffle_f64x2(u[2], u[6], _MM_SHUFFLE(2, 0, 2, 0));
    c[5] = _mm512_shuffle_f64x2(u[2], u[6], _MM_SHUFFLE(3, 1, 3, 1));
    c[3] = _mm512_shuffle_f64x2(u[3], u[7], _MM_SHUFFLE(2, 0, 2, 0));
    c[7] = _mm512_shuffle_f64x2(u[3], u[7], _MM_SHUFFLE(3, 1, 3, 1));
  }

  MPUMESH_SIMD_TARGET static void load_leaves(const double* const* p, V* F) {
    for (int blk = 0; blk < 4; ++blk) {
      V r[8];
      for (int l = 0; l < 8; ++l) r[l] = _mm512_loadu_pd(p[l] + 8 * blk);
      transpose(r, F + 8 * blk);
    }
    // Doubles 32-35 (the last coefficients and the leaf's kind, degree, depth and count,
    // read but unused), two leaves a register, then a 4 x 8 transpose as in `support`.
    V z[4];
    for (int k = 0; k < 4; ++k)
      z[k] = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(p[2 * k] + 32)), _mm256_loadu_pd(p[2 * k + 1] + 32), 1);
    const __m512i lo = _mm512_setr_epi64(0, 4, 1, 5, 8, 12, 9, 13), hi = _mm512_setr_epi64(2, 6, 3, 7, 10, 14, 11, 15);
    const V t0 = _mm512_unpacklo_pd(z[0], z[1]), t1 = _mm512_unpackhi_pd(z[0], z[1]);
    const V t2 = _mm512_unpacklo_pd(z[2], z[3]), t3 = _mm512_unpackhi_pd(z[2], z[3]);
    F[32] = _mm512_permutex2var_pd(t0, lo, t2);
    F[34] = _mm512_permutex2var_pd(t0, hi, t2);
    F[33] = _mm512_permutex2var_pd(t1, lo, t3);
    F[35] = _mm512_permutex2var_pd(t1, hi, t3);
  }

  MPUMESH_SIMD_TARGET static int support(const double* spheres, const uint32_t* ids, int count, V px, V py, V pz,
                                         uint32_t* out) {
    uint32_t tail[8];
    if (count < 8) {  // a cell's last few: the rest of the lanes test the first again
      for (int l = 0; l < 8; ++l) tail[l] = ids[l < count ? l : 0];
      ids = tail;
    }
    const uint32_t* id = ids;
    // Two spheres per register, then a 4 x 8 transpose: cx, cy, cz, R² of the eight.
    V z[4];
    for (int k = 0; k < 4; ++k)
      z[k] = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(spheres + 4 * size_t(id[2 * k]))),
                                _mm256_loadu_pd(spheres + 4 * size_t(id[2 * k + 1])), 1);
    const __m512i lo = _mm512_setr_epi64(0, 4, 1, 5, 8, 12, 9, 13), hi = _mm512_setr_epi64(2, 6, 3, 7, 10, 14, 11, 15);
    const V t0 = _mm512_unpacklo_pd(z[0], z[1]), t1 = _mm512_unpackhi_pd(z[0], z[1]);
    const V t2 = _mm512_unpacklo_pd(z[2], z[3]), t3 = _mm512_unpackhi_pd(z[2], z[3]);
    const V cx = _mm512_permutex2var_pd(t0, lo, t2), cz = _mm512_permutex2var_pd(t0, hi, t2);
    const V cy = _mm512_permutex2var_pd(t1, lo, t3), R2 = _mm512_permutex2var_pd(t1, hi, t3);
    const V dx = sub(px, cx), dy = sub(py, cy), dz = sub(pz, cz);
    const V r2 = add(add(mul(dx, dx), mul(dy, dy)), mul(dz, dz));
    const Mask valid = Mask((1u << count) - 1);
    const Mask hit = _mm512_mask_cmp_pd_mask(valid, r2, R2, _CMP_LT_OQ);
    // Compacted in a register and stored whole (vpcompressd to memory is slow on Intel);
    // `out` has room for 8 past the last hit.
    const __m256i idv = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(id));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_maskz_compress_epi32(hit, idv));
    return __builtin_popcount(hit);
  }
};


// The single-precision kernel's vectors: 16 floats, a 16-bit mask; its support test is
// the double one's above.
struct Avx512F {
  using T = float;
  static constexpr int kLanes = 16;
  using Support = Avx512;
  using V = __m512;
  using Mask = __mmask16;
  MPUMESH_SIMD_TARGET static V set1(double a) { return _mm512_set1_ps(float(a)); }
  MPUMESH_SIMD_TARGET static V zero() { return _mm512_setzero_ps(); }
  MPUMESH_SIMD_TARGET static V add(V a, V b) { return _mm512_add_ps(a, b); }
  MPUMESH_SIMD_TARGET static V sub(V a, V b) { return _mm512_sub_ps(a, b); }
  MPUMESH_SIMD_TARGET static V mul(V a, V b) { return _mm512_mul_ps(a, b); }
  MPUMESH_SIMD_TARGET static V div(V a, V b) { return _mm512_div_ps(a, b); }
  MPUMESH_SIMD_TARGET static V sqrt(V a) { return _mm512_sqrt_ps(a); }
  MPUMESH_SIMD_TARGET static Mask lt(V a, V b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
  MPUMESH_SIMD_TARGET static Mask le(V a, V b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
  MPUMESH_SIMD_TARGET static V sel(Mask m, V t, V f) { return _mm512_mask_blend_ps(m, f, t); }
  MPUMESH_SIMD_TARGET static V keep(Mask m, V a) { return _mm512_maskz_mov_ps(m, a); }
  MPUMESH_SIMD_TARGET static float first(V a) { return _mm512_cvtss_f32(a); }
  MPUMESH_SIMD_TARGET static void store(float* p, V a) { _mm512_storeu_ps(p, a); }
  MPUMESH_SIMD_TARGET static Mask lanes_from(int k) { return Mask(0xffffu << k); }
  MPUMESH_SIMD_TARGET static const float* record(const EvalView& v, uint32_t id) {
    return v.records32 + size_t(id) * 36;
  }

  // A 16 x 16 transpose: pairs, then 4 x 4 blocks within 128-bit lanes, then the 4 x 4
  // transpose of the 128-bit lanes.
  MPUMESH_SIMD_TARGET static void transpose(const V r[16], V* c) {
    V t[16], u[16];
    for (int i = 0; i < 8; ++i) {
      t[2 * i] = _mm512_unpacklo_ps(r[2 * i], r[2 * i + 1]);
      t[2 * i + 1] = _mm512_unpackhi_ps(r[2 * i], r[2 * i + 1]);
    }
    // u[4 i + k], 128-bit lane m: column 4 m + k of rows 4 i .. 4 i + 3.
    for (int i = 0; i < 4; ++i) {
      u[4 * i + 0] = _mm512_shuffle_ps(t[4 * i + 0], t[4 * i + 2], 0x44);
      u[4 * i + 1] = _mm512_shuffle_ps(t[4 * i + 0], t[4 * i + 2], 0xEE);
      u[4 * i + 2] = _mm512_shuffle_ps(t[4 * i + 1], t[4 * i + 3], 0x44);
      u[4 * i + 3] = _mm512_shuffle_ps(t[4 * i + 1], t[4 * i + 3], 0xEE);
    }
    for (int k = 0; k < 4; ++k) {
      const V v0 = _mm512_shuffle_f32x4(u[k], u[4 + k], 0x88), v1 = _mm512_shuffle_f32x4(u[k], u[4 + k], 0xDD);
      const V v2 = _mm512_shuffle_f32x4(u[8 + k], u[12 + k], 0x88), v3 = _mm512_shuffle_f32x4(u[8 + k], u[12 + k], 0xDD);
      c[k] = _mm512_shuffle_f32x4(v0, v2, 0x88);
      c[8 + k] = _mm512_shuffle_f32x4(v0, v2, 0xDD);
      c[4 + k] = _mm512_shuffle_f32x4(v1, v3, 0x88);
      c[12 + k] = _mm512_shuffle_f32x4(v1, v3, 0xDD);
    }
  }

  MPUMESH_SIMD_TARGET static void load_leaves(const float* const* p, V* F) {
    for (int blk = 0; blk < 2; ++blk) {
      V r[16];
      for (int l = 0; l < 16; ++l) r[l] = _mm512_loadu_ps(p[l] + 16 * blk);
      transpose(r, F + 16 * blk);
    }
    // Numbers 32-35, four leaves a register (z[k], 128-bit lane m: leaf 4 k + m), then
    // e[j], 128-bit lane m, element k: number 32 + j of leaf 4 k + m; a permutation puts
    // leaf 4 k + m in lane 4 k + m.
    V z[4];
    for (int k = 0; k < 4; ++k) {
      V a = _mm512_castps128_ps512(_mm_loadu_ps(p[4 * k] + 32));
      a = _mm512_insertf32x4(a, _mm_loadu_ps(p[4 * k + 1] + 32), 1);
      a = _mm512_insertf32x4(a, _mm_loadu_ps(p[4 * k + 2] + 32), 2);
      z[k] = _mm512_insertf32x4(a, _mm_loadu_ps(p[4 * k + 3] + 32), 3);
    }
    const V a = _mm512_unpacklo_ps(z[0], z[1]), b = _mm512_unpackhi_ps(z[0], z[1]);
    const V c = _mm512_unpacklo_ps(z[2], z[3]), d = _mm512_unpackhi_ps(z[2], z[3]);
    const V e[4] = {_mm512_shuffle_ps(a, c, 0x44), _mm512_shuffle_ps(a, c, 0xEE), _mm512_shuffle_ps(b, d, 0x44),
                    _mm512_shuffle_ps(b, d, 0xEE)};
    const __m512i lane_of = _mm512_setr_epi32(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15);
    for (int j = 0; j < 4; ++j) F[32 + j] = _mm512_permutexvar_ps(lane_of, e[j]);
  }
};

}  // namespace
}  // namespace mpumesh::mpu::simd

#include "mpu/mpu_eval_simd_kernel.h"

namespace mpumesh::mpu::simd {

MPUMESH_SIMD_TARGET EvalOut evaluate_avx512(const EvalView& v, const double x[3], int order) {
  return eval_dispatch<Avx512>(v, x, order);
}

MPUMESH_SIMD_TARGET EvalOut evaluate_f32_avx512(const EvalView& v, const double x[3], int order) {
  return eval_dispatch<Avx512F>(v, x, order);
}

}  // namespace mpumesh::mpu::simd

#endif  // x86-64 (elsewhere mpu_eval_simd.cpp defines the entry point)
