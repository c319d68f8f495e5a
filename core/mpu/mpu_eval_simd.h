// The MPU evaluation's vector paths: the loop of mpu_eval_ref.cpp (f, ∇f and the Hessian
// at one point, its leaves found through the lookup grid) written with explicit AVX-512
// or AVX2 instructions, eight leaves at a time, and chosen at run time by what the CPU
// supports. Every lane does the reference's operations in the reference's order (no
// fused multiply-add, the same eight running sums, the same padding of the last eight),
// so each path gives the reference's bytes; tests/core/mpu/test_mpu_eval_simd.cpp checks
// that on phantoms and random points. What the vectors buy is fewer instructions: the
// reference copies each leaf field by field into structure-of-arrays form, 29 scalar
// moves a leaf, where the vector paths load a leaf in four 8-double loads and transpose
// eight leaves in registers; and the support test runs on eight candidates at once.
// common/simd_level.h picks the path (MPUMESH_SIMD=generic|avx2|avx512).
// (No gathers: an 8-double gather costs about 23 cycles on current x86 cores, more than
// the scalar copy.)
//
// The kernels see the surface only through EvalView, plain pointers, so that their
// translation units instantiate no Eigen or standard-library template under another
// instruction set (such a copy could be the one the linker keeps for every caller).
#pragma once

#include <cstdint>
#include <string>

namespace mpumesh::mpu {

struct MpuSurface;

namespace simd {

// What a kernel needs of the surface (mpu_surface.h): the lookup grid, the compact
// spheres (cx, cy, cz, R² per leaf) and the leaves themselves, whose first 35 doubles
// are centre (3), radius, frame (9, column-major) and coefficients (22); the kernels read
// 36 (the leaf's record is at least that long).
struct EvalView {
  double box_min[3];
  double box_size;
  uint32_t dims[3];
  const uint32_t* offsets;
  const uint32_t* leaf_ids;
  const double* spheres;
  const double* leaves;
  uint32_t leaf_stride;  // doubles per leaf
  // The leaves' first 36 numbers as floats, 36 per leaf (LookupGrid::records32), for the
  // float kernels; null where the surface has none.
  const float* records32;
};

// Result of one evaluation: f, ∇f, the blended Hessian Hb and the Hessian H of f (xx xy
// xz yy yz zz; mpu_eval_ref.h), the leaves that hold the point; `handled` is false where
// the kernel declined (a lookup cell with more candidates than it buffers), and the
// caller then runs the reference.
struct EvalOut {
  double f = 0, g[3] = {0, 0, 0}, Hb[6] = {0, 0, 0, 0, 0, 0}, H[6] = {0, 0, 0, 0, 0, 0};
  int leaves = 0;
  bool handled = true;
};

// The most candidates of one lookup cell that the kernels buffer on the stack.
inline constexpr uint32_t kMaxCandidates = 1024;

EvalView make_view(const MpuSurface& s);

// order 0: f; 1: f and ∇f; 2: f, ∇f and Hb; 3: f, ∇f, Hb and H.
EvalOut evaluate_avx512(const EvalView& v, const double x[3], int order);
EvalOut evaluate_avx2(const EvalView& v, const double x[3], int order);
// The single-precision kernels (common/eval_precision.h): 16 leaves a step, sums in
// float, the support test in double; the same bytes at each level.
EvalOut evaluate_f32_avx512(const EvalView& v, const double x[3], int order);
EvalOut evaluate_f32_avx2(const EvalView& v, const double x[3], int order);
EvalOut evaluate_f32_generic(const EvalView& v, const double x[3], int order);

}  // namespace simd
}  // namespace mpumesh::mpu
