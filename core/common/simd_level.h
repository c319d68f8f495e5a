// The vector instruction set the CPU path's hand-vectorised kernels use (the MPU
// evaluation, core/mpu/mpu_eval_simd.h; the repulsion's neighbour filter and pair sums,
// core/particles/pair_filter.h and pair_sums.h): the widest this CPU supports, or the
// one MPUMESH_SIMD names (generic, avx2, avx512) when that is supported. Every level
// gives the same bytes as the generic code; the levels differ in speed only.
#pragma once

// Where the AVX2 and AVX-512 kernels are built (x86-64, GCC or clang target attributes);
// elsewhere only the generic code runs.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MPUMESH_X86_SIMD 1
#else
#define MPUMESH_X86_SIMD 0
#endif

namespace mpumesh {

enum class SimdLevel { kGeneric, kAvx2, kAvx512 };

const char* simd_level_name(SimdLevel l);
// Whether this CPU (and this build) can run level l; kGeneric always.
bool simd_level_supported(SimdLevel l);
SimdLevel simd_level();
// For tests and benchmarks: use l from now on (it must be supported).
void set_simd_level(SimdLevel l);

}  // namespace mpumesh
