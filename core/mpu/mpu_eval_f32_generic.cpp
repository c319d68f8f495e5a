// The generic path of the single-precision MPU evaluation (mpu_eval_simd.h): the vector
// kernel over vectors of 16 floats (GCC's vector extension), which the compiler maps onto
// whatever vector unit the baseline target has. Its operations are the AVX2 and AVX-512 float kernels', lane for
// lane (no multiply-add contraction in this file either), so every level gives the same
// bytes. The support test is the double-precision reference's.
#include <cmath>
#include <cstdint>

#include "mpu/mpu_eval_simd.h"

#define MPUMESH_SIMD_TARGET

namespace mpumesh::mpu::simd {
namespace {

struct GenericD {
  struct V {
    double x;
  };
  static V set1(double a) { return {a}; }
  // The ids among `count` whose sphere holds the point, in order.
  static int support(const double* spheres, const uint32_t* ids, int count, V px, V py, V pz, uint32_t* out) {
    int n = 0;
    for (int k = 0; k < count; ++k) {
      const double* sp = spheres + 4 * size_t(ids[k]);
      const double dx = px.x - sp[0], dy = py.x - sp[1], dz = pz.x - sp[2];
      const double r2 = dx * dx + dy * dy + dz * dz;
      out[n] = ids[k];
      n += r2 < sp[3];
    }
    return n;
  }
};

struct GenericF {
  using T = float;
  static constexpr int kLanes = 16;
  using Support = GenericD;
  // GCC's vector extension: the compiler splits the 16 lanes into the registers the
  // target has (four SSE registers on baseline x86-64).
  typedef float V __attribute__((vector_size(64)));
  typedef int32_t Mask __attribute__((vector_size(64)));  // -1 where set
  static V set1(double a) { return V{} + float(a); }
  static V zero() { return V{}; }
  static V add(V a, V b) { return a + b; }
  static V sub(V a, V b) { return a - b; }
  static V mul(V a, V b) { return a * b; }
  static V div(V a, V b) { return a / b; }
  static V sqrt(V a) {
    for (int l = 0; l < 16; ++l) a[l] = __builtin_sqrtf(a[l]);
    return a;
  }
  static Mask lt(V a, V b) { return a < b; }
  static Mask le(V a, V b) { return a <= b; }
  static V sel(Mask m, V t, V f) { return m ? t : f; }
  static V keep(Mask m, V a) { return m ? a : V{}; }
  static float first(V a) { return a[0]; }
  static void store(float* p, V a) {
    for (int l = 0; l < 16; ++l) p[l] = a[l];
  }
  static Mask lanes_from(int k) {
    const Mask lane = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    return lane >= k;
  }
  static const float* record(const EvalView& v, uint32_t id) { return v.records32 + size_t(id) * 36; }
  static void load_leaves(const float* const* p, V* F) {
    for (int k = 0; k < 36; ++k)
      for (int l = 0; l < 16; ++l) F[k][l] = p[l][k];
  }
};

}  // namespace
}  // namespace mpumesh::mpu::simd

#include "mpu/mpu_eval_simd_kernel.h"

namespace mpumesh::mpu::simd {

EvalOut evaluate_f32_generic(const EvalView& v, const double x[3], int order) {
  return eval_dispatch<GenericF>(v, x, order);
}

}  // namespace mpumesh::mpu::simd
