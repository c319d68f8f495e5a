// Data contract of the multi-material sampling kernel (complex_step.comp) and its CPU
// reference (core/multi/complex_step_ref.cpp). Positions are in millimetres relative to
// an origin the host chooses (the centre of the fits' boxes), as in mpu_abi.h.
// The material field (core/multi/material_field.h):
//   leaves, offsets, leaf_ids  every fit's, concatenated (MpuGridRef's bases locate one)
//   fits      CxFit per fit: the labels' (region r is fit r - 1), then the parts' contact
//             unions, then the labels' union (the background's function), when present
//   regions   CxRegion per region: its support box in voxels and the first word of its
//             support bits, and for a part its contact group (-1: none)
//   support   the regions' support bits (a bit per voxel of each box, x fastest)
// Per particle: in (x, y, z, spacing), in_regions (ascending, -1 unused) and in_kind
// (CX_KIND_*); the relaxations' neighbours as CSR (first, neighbours); out (x, y, z, 0),
// out_regions and out_state (bit 0: ok; bits 1-3: the kind).
#ifndef MPUMESH_COMPLEX_ABI_H
#define MPUMESH_COMPLEX_ABI_H
#include "shared/abi_prelude.h"

#define CX_BIND_LEAVES 0
#define CX_BIND_OFFSETS 1
#define CX_BIND_LEAF_IDS 2
#define CX_BIND_FITS 3         // CxFit[fits]
#define CX_BIND_REGIONS 4      // CxRegion[regions]
#define CX_BIND_SUPPORT 5      // uint[]
#define CX_BIND_IN 6           // vec4[count]: x, y, z, spacing
#define CX_BIND_IN_REGIONS 7   // ivec4[count]
#define CX_BIND_IN_KIND 8      // uint[count]
#define CX_BIND_FIRST 9        // uint[count + 1]
#define CX_BIND_NEIGHBOURS 10  // uint[]
#define CX_BIND_OUT 11         // vec4[count]
#define CX_BIND_OUT_REGIONS 12 // ivec4[count]
#define CX_BIND_OUT_STATE 13   // uint[count]

#define CX_STEP_ONTO_INTERFACE 0u
#define CX_STEP_JUNCTION_CANDIDATE 1u
#define CX_STEP_RELAX_JUNCTION 2u
#define CX_STEP_RELAX_INTERFACE 3u

#define CX_KIND_INTERFACE 2u
#define CX_KIND_JUNCTION 3u
#define CX_KIND_CORNER 4u

#define CX_NONE 0xffffffffu

ABI_BEGIN
struct CxFit {
  vec4 grid_min;  // lookup grid's corner xyz, 1 / cell size
  uvec4 dims;     // lookup grid's dims, leaf_base
  uvec4 bases;    // offset_base, id_base, 0, 0
  vec4 data_min;  // where the fit holds (mpu/data_box.h): its lower corner, far value
  vec4 data_max;  // upper corner, 0
};
struct CxRegion {
  uvec4 lo;  // support box's lowest voxel xyz, first support word
  uvec4 hi;  // one past its highest voxel xyz, contact group + 1 (0: none)
};
struct ComplexPush {
  uint count;    // particles
  uint row;      // invocations per dispatch row
  uint step;     // CX_STEP_*
  uint regions;  // the background and the labels or parts
  uint outside;  // the labels' union's fit, or CX_NONE
  uint unions;   // the parts' contact unions (fits regions - 1 ...)
  uint support;  // 1: the regions' supports bound
  float contact; // the parts' contact distance (mm)
  // Voxel index = round(to_index * (x - map_origin)), to_index the map's inverse
  // direction over its spacing, rows; map_origin relative to the positions' origin.
  float to_index[9];
  float map_origin[3];
  uint map_dims[3];
  float depth;   // a label map's: where its labels compare inside their union (mm)
};
ABI_END

#ifdef __cplusplus
static_assert(sizeof(mpumesh::abi::CxFit) == 80, "CxFit must match the GLSL struct");
static_assert(sizeof(mpumesh::abi::CxRegion) == 32, "CxRegion must match the GLSL struct");
static_assert(sizeof(mpumesh::abi::ComplexPush) == 96, "ComplexPush must match the GLSL push block");
#endif
#endif
