// The .mpu file: an MPU surface (core/mpu/mpu_surface.h) as written by `mpumesh fit` and
// read by eval, polygonize, sample and triangulate. Version 2, little-endian throughout:
//
//   offset  size  field
//   0       8     magic 89 'M' 'P' 'U' 0D 0A 1A 0A (a text-mode copy or a truncation by
//                 a line-ending conversion shows up at once, as in PNG)
//   8       4     u32 version = 2
//   12      4     u32 flags = 0 (reserved)
//   16      24    f64 box_min x, y, z (mm): the bounding cube's lowest corner
//   40      8     f64 box_size (mm): its side
//   48      4     u32 leaf count L
//   52      12    u32 grid dims nx, ny, nz: the lookup grid over the cube
//   64      4     u32 grid entry count E (length of leaf_ids)
//   68      4     u32 reserved = 0
//   72      48    f64 data_min x, y, z, data_max x, y, z (mm): the fitted points' bounding
//                 box, inside the cube
//   120     L*288 leaves, each: f64 centre[3], f64 radius, f64 frame[9] (rows u, v, w),
//                 f64 coeffs[22] (the local basis of core/mpu/local_poly.h), u8 kind
//                 (0 orthopoly height field, 1 quadric height field, 2 general quadric,
//                 3 two sheets), u8 degree, u8 depth, u8 reserved, u32 point count
//   ...     4*(nx*ny*nz+1)  u32 grid offsets (CSR, non-decreasing, first 0, last E)
//   ...     4*E   u32 leaf ids, each < L
//   ...     4     u32 CRC-32 (zlib's) of every byte before it
//
// Version 1 differs only in its leaves: 264 bytes, 19 coefficients (the rest are zero),
// kinds 0-2; it is still read. A file that is short, long, has another magic or an unknown
// version, a wrong CRC, or values out of range (non-finite numbers, radius <= 0, an
// unknown kind, ids past the end) is refused with an InputError that names the file and
// the problem.
#pragma once

#include <string>

#include "mpu/mpu_surface.h"

namespace mpumesh::mpu {

inline constexpr uint32_t kMpuFileVersion = 2;
// The coefficients a leaf holds in a file of `version`, and its highest fit kind.
inline constexpr size_t coefficients_in(uint32_t version) { return version >= 2 ? 22 : 19; }
inline constexpr uint8_t kind_limit(uint32_t version) { return version >= 2 ? 3 : 2; }

std::string serialize_mpu(const MpuSurface& s);
// `name` appears in error messages.
MpuSurface parse_mpu(const std::string& bytes, const std::string& name);

// Atomic: a failed write leaves any previous file untouched.
void write_mpu(const MpuSurface& s, const std::string& path);
MpuSurface read_mpu(const std::string& path);

}  // namespace mpumesh::mpu
