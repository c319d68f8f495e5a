// The .mpu file: an MPU surface (core/mpu/mpu_surface.h) as written by `mpumesh fit` and
// read by eval, polygonize, sample and triangulate. Version 1, little-endian throughout:
//
//   offset  size  field
//   0       8     magic 89 'M' 'P' 'U' 0D 0A 1A 0A (a text-mode copy or a truncation by
//                 a line-ending conversion shows up at once, as in PNG)
//   8       4     u32 version = 1
//   12      4     u32 flags = 0 (reserved)
//   16      24    f64 box_min x, y, z (mm): the bounding cube's lowest corner
//   40      8     f64 box_size (mm): its side
//   48      4     u32 leaf count L
//   52      12    u32 grid dims nx, ny, nz: the lookup grid over the cube
//   64      4     u32 grid entry count E (length of leaf_ids)
//   68      4     u32 reserved = 0
//   72      48    f64 data_min x, y, z, data_max x, y, z (mm): the fitted points' bounding
//                 box, inside the cube
//   120     L*264 leaves, each: f64 centre[3], f64 radius, f64 frame[9] (rows u, v, w),
//                 f64 coeffs[19] (the local basis of core/mpu/local_poly.h), u8 kind
//                 (0 orthopoly height field, 1 quadric height field, 2 general quadric),
//                 u8 degree, u8 depth, u8 reserved, u32 point count
//   ...     4*(nx*ny*nz+1)  u32 grid offsets (CSR, non-decreasing, first 0, last E)
//   ...     4*E   u32 leaf ids, each < L
//   ...     4     u32 CRC-32 (zlib's) of every byte before it
//
// A file that is short, long, has another magic or version, a wrong CRC, or values out of
// range (non-finite numbers, radius <= 0, an unknown kind, ids past the end) is refused
// with an InputError that names the file and the problem.
#pragma once

#include <string>

#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

inline constexpr uint32_t kMpuFileVersion = 1;

std::string serialize_mpu(const MpuSurface& s);
// `name` appears in error messages.
MpuSurface parse_mpu(const std::string& bytes, const std::string& name);

// Atomic: a failed write leaves any previous file untouched.
void write_mpu(const MpuSurface& s, const std::string& path);
MpuSurface read_mpu(const std::string& path);

}  // namespace mpumesh::mpu
