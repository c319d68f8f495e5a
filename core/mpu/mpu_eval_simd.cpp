#include "mpu/mpu_eval_simd.h"

#include "common/error.h"
#include "common/simd_level.h"
#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

namespace {

// The kernels read a leaf's first 36 doubles as centre, radius, frame (column-major),
// coefficients and the rest of the record (mpu_eval_simd.h).
bool leaf_layout_as_the_kernels_read_it() {
  const Leaf l;
  const double* b = reinterpret_cast<const double*>(&l);
  return sizeof(Leaf) % sizeof(double) == 0 && l.centre.data() == b && &l.radius == b + 3 && l.frame.data() == b + 4 &&
         l.coeffs.data() == b + 13 && sizeof(Leaf) / sizeof(double) >= 36;
}

}  // namespace

namespace simd {

EvalView make_view(const MpuSurface& s) {
  static const bool layout_ok = leaf_layout_as_the_kernels_read_it();
  MPUMESH_ASSERT(layout_ok, "mpu::Leaf's layout is not the one the vector kernels read");
  EvalView v;
  for (int d = 0; d < 3; ++d) {
    v.box_min[d] = s.box_min[d];
    v.dims[d] = s.grid.dims[size_t(d)];
  }
  v.box_size = s.box_size;
  v.offsets = s.grid.offsets.data();
  v.leaf_ids = s.grid.leaf_ids.data();
  v.spheres = s.grid.spheres.empty() ? nullptr : s.grid.spheres.front().data();
  v.leaves = reinterpret_cast<const double*>(s.leaves.data());
  v.leaf_stride = uint32_t(sizeof(Leaf) / sizeof(double));
  v.records32 = s.grid.records32.size() == s.leaves.size() * LookupGrid::kRecord32 && !s.leaves.empty()
                    ? s.grid.records32.data()
                    : nullptr;
  return v;
}

}  // namespace simd
}  // namespace mpumesh::mpu

#if !MPUMESH_X86_SIMD
// Without x86-64 vector units only the generic path runs (simd_level_supported), so these
// are never called.
namespace mpumesh::mpu::simd {
EvalOut evaluate_avx512(const EvalView&, const double*, int) {
  MPUMESH_ASSERT(false, "the AVX-512 evaluation path is not built for this target");
  return {};
}
EvalOut evaluate_avx2(const EvalView&, const double*, int) {
  MPUMESH_ASSERT(false, "the AVX2 evaluation path is not built for this target");
  return {};
}
EvalOut evaluate_f32_avx512(const EvalView&, const double*, int) {
  MPUMESH_ASSERT(false, "the AVX-512 evaluation path is not built for this target");
  return {};
}
EvalOut evaluate_f32_avx2(const EvalView&, const double*, int) {
  MPUMESH_ASSERT(false, "the AVX2 evaluation path is not built for this target");
  return {};
}
}  // namespace mpumesh::mpu::simd
#endif
