#include "mpu/mpu_eval_simd.h"

#include <atomic>
#include <cstdlib>
#include <cstring>

#include "common/error.h"
#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

const char* eval_path_name(EvalPath p) {
  switch (p) {
    case EvalPath::kAvx512: return "avx512";
    case EvalPath::kAvx2: return "avx2";
    default: return "generic";
  }
}

bool eval_path_supported(EvalPath p) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  switch (p) {
    case EvalPath::kAvx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
    case EvalPath::kAvx2: return __builtin_cpu_supports("avx2");
    default: return true;
  }
#else
  return p == EvalPath::kGeneric;
#endif
}

namespace {

// The kernels read a leaf's first 32 doubles as centre, radius, frame (column-major) and
// coefficients (mpu_eval_simd.h).
bool leaf_layout_as_the_kernels_read_it() {
  const Leaf l;
  const double* b = reinterpret_cast<const double*>(&l);
  return sizeof(Leaf) % sizeof(double) == 0 && l.centre.data() == b && &l.radius == b + 3 && l.frame.data() == b + 4 &&
         l.coeffs.data() == b + 13 && sizeof(Leaf) / sizeof(double) >= 32;
}

EvalPath initial_path() {
  MPUMESH_ASSERT(leaf_layout_as_the_kernels_read_it(), "mpu::Leaf's layout is not the one the vector kernels read");
  if (const char* env = std::getenv("MPUMESH_EVAL_PATH")) {
    for (EvalPath p : {EvalPath::kGeneric, EvalPath::kAvx2, EvalPath::kAvx512})
      if (std::strcmp(env, eval_path_name(p)) == 0 && eval_path_supported(p)) return p;
  }
  if (eval_path_supported(EvalPath::kAvx512)) return EvalPath::kAvx512;
  if (eval_path_supported(EvalPath::kAvx2)) return EvalPath::kAvx2;
  return EvalPath::kGeneric;
}

std::atomic<EvalPath>& current() {
  static std::atomic<EvalPath> path{initial_path()};
  return path;
}

}  // namespace

EvalPath eval_path() { return current().load(std::memory_order_relaxed); }

void set_eval_path(EvalPath p) {
  MPUMESH_ASSERT(eval_path_supported(p), std::string("evaluation path ") + eval_path_name(p) + " not supported here");
  current().store(p, std::memory_order_relaxed);
}

namespace simd {

EvalView make_view(const MpuSurface& s) {
  EvalView v;
  for (int d = 0; d < 3; ++d) {
    v.box_min[d] = s.box_min[d];
    v.dims[d] = s.grid.dims[size_t(d)];
  }
  v.box_size = s.box_size;
  v.offsets = s.grid.offsets.data();
  v.leaf_ids = s.grid.leaf_ids.data();
  v.spheres = s.grid.spheres.data()->data();
  v.leaves = reinterpret_cast<const double*>(s.leaves.data());
  v.leaf_stride = uint32_t(sizeof(Leaf) / sizeof(double));
  return v;
}

}  // namespace simd
}  // namespace mpumesh::mpu
