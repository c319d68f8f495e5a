#include "common/simd_level.h"

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/error.h"

namespace mpumesh {

const char* simd_level_name(SimdLevel l) {
  switch (l) {
    case SimdLevel::kAvx512: return "avx512";
    case SimdLevel::kAvx2: return "avx2";
    default: return "generic";
  }
}

bool simd_level_supported(SimdLevel l) {
#if MPUMESH_X86_SIMD
  switch (l) {
    case SimdLevel::kAvx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
    case SimdLevel::kAvx2: return __builtin_cpu_supports("avx2");
    default: return true;
  }
#else
  return l == SimdLevel::kGeneric;
#endif
}

namespace {

SimdLevel initial_level() {
  if (const char* env = std::getenv("MPUMESH_SIMD")) {
    for (SimdLevel l : {SimdLevel::kGeneric, SimdLevel::kAvx2, SimdLevel::kAvx512})
      if (std::strcmp(env, simd_level_name(l)) == 0 && simd_level_supported(l)) return l;
  }
  if (simd_level_supported(SimdLevel::kAvx512)) return SimdLevel::kAvx512;
  if (simd_level_supported(SimdLevel::kAvx2)) return SimdLevel::kAvx2;
  return SimdLevel::kGeneric;
}

std::atomic<SimdLevel>& current() {
  static std::atomic<SimdLevel> level{initial_level()};
  return level;
}

}  // namespace

SimdLevel simd_level() { return current().load(std::memory_order_relaxed); }

void set_simd_level(SimdLevel l) {
  MPUMESH_ASSERT(simd_level_supported(l), std::string("vector level ") + simd_level_name(l) + " not supported here");
  current().store(l, std::memory_order_relaxed);
}

}  // namespace mpumesh
