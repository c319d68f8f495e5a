// Data contract of the MPU evaluation kernel (mpu_eval.comp) and its CPU reference
// (core/mpu/mpu_eval_ref.cpp). Positions are in millimetres relative to an origin the
// host chooses (the bounding cube's centre), so that float32 keeps about 1e-5 mm of
// resolution across a head-sized volume. Each leaf is 9 vec4:
//   [0] centre.xyz, R      [1] frame row u.xyz, 1/R   [2] row v.xyz, c19   [3] row w.xyz, c20
//   [4..8] coefficients 0-18 of core/mpu/local_poly.h, then c21.
// The lookup grid is CSR: offsets[cell], offsets[cell + 1] bound the cell's run of
// leaf_ids. Output per point: vec4 (f, ∇f) and vec4 (κ1, κ2, K, mean curvature); with
// value_only set, vec4 (f, ∇f) alone (no Hessian; the curvature buffer is not written).
#ifndef MPUMESH_MPU_ABI_H
#define MPUMESH_MPU_ABI_H
#include "shared/abi_prelude.h"

#define MPU_BIND_LEAVES 0    // vec4[9 * leaves]
#define MPU_BIND_OFFSETS 1   // uint[cells + 1]
#define MPU_BIND_LEAF_IDS 2  // uint[entries]
#define MPU_BIND_POINTS 3    // vec4[count]: xyz, w ignored
#define MPU_BIND_FG 4        // vec4[count]: f, gx, gy, gz
#define MPU_BIND_CURV 5      // vec4[count]: k1, k2, K, H

#define MPU_LEAF_VEC4 9

ABI_BEGIN
struct MpuPush {
  float box_min_x, box_min_y, box_min_z;  // relative to the origin
  float inv_cell;                         // 1 / grid cell size
  uint nx, ny, nz;                        // grid dims
  float far_value;                        // f where no leaf holds the point
  uint count;                             // points
  uint row;                               // invocations per dispatch row
  uint value_only;                        // 1: f and ∇f only
  uint pad1;
};
ABI_END

#ifdef __cplusplus
static_assert(sizeof(mpumesh::abi::MpuPush) == 48, "MpuPush must match the GLSL push block");
#endif
#endif
