// Data contract of the Chan-Vese kernels (chan_vese_means.comp, chan_vese_update.comp) and their CPU
// reference (core/segment/chan_vese_ref.cpp). The stack holds nz slices of nx * ny
// pixels, x fastest. u is the windowed image (integers 0..255 stored as float), phi the
// level set (inside: phi >= 0). Each iteration: chan_vese_means reduces per slice the exact
// integer sum and count of u inside and outside and writes the region means (c1, c2);
// chan_vese_update takes one semi-implicit Jacobi step from phi_in to phi_out.
#ifndef MPUMESH_CV_ABI_H
#define MPUMESH_CV_ABI_H
#include "shared/abi_prelude.h"

#define CV_BIND_U 0        // float[nx * ny * nz]
#define CV_BIND_PHI_IN 1   // float[nx * ny * nz]
#define CV_BIND_PHI_OUT 2  // float[nx * ny * nz]
#define CV_BIND_MEANS 3    // vec4[nz]: c1, c2, inside count, 0

// c1 when a slice has no inside pixel and c2 when it has no outside pixel: the ends of
// the window, so that an empty slice does not start to grow.
#define CV_EMPTY_C1 255.0
#define CV_EMPTY_C2 0.0

ABI_BEGIN
struct CvPush {
  uint nx, ny, nz;
  uint row;        // invocations per dispatch row (2D dispatch of large stacks)
  float lambda1, lambda2, mu, nu;
  float dt, epsilon, eta, pad0;
  uint pad1, pad2, pad3, pad4;
};
ABI_END

#ifdef __cplusplus
static_assert(sizeof(mpumesh::abi::CvPush) == 64, "CvPush must match the GLSL push block");
#endif
#endif
