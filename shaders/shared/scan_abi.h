// Data contract of the exclusive prefix sum (scan_blocks.comp, scan_add.comp) over uint
// arrays: each workgroup scans 4 * local_size_x elements and writes its total to sums[].
#ifndef MPUMESH_SCAN_ABI_H
#define MPUMESH_SCAN_ABI_H
#include "shared/abi_prelude.h"

#define SCAN_BIND_DATA 0  // uint[count], scanned in place (exclusive)
#define SCAN_BIND_SUMS 1  // uint[blocks]: per-block totals
#define SCAN_ITEMS_PER_THREAD 4

ABI_BEGIN
struct ScanPush {
  uint count;
  uint row_groups;  // workgroups per dispatch row (2D dispatch of large arrays)
  uint pad0, pad1;
};
ABI_END

#ifdef __cplusplus
static_assert(sizeof(mpumesh::abi::ScanPush) == 16, "ScanPush must match the GLSL push block");
#endif
#endif
