#include "kernels/scan_vk.h"

#include "scan_add.spv.h"
#include "scan_blocks.spv.h"
#include "shared/scan_abi.h"

namespace mpumesh::vk {
namespace {
const std::vector<Binding> kBindings = {{SCAN_BIND_DATA, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                        {SCAN_BIND_SUMS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
}

ScanKernel::ScanKernel(Context& ctx)
    : ctx_(ctx),
      blocks_(ctx, kSpv_scan_blocks, kBindings, sizeof(abi::ScanPush), default_workgroup_size(ctx)),
      add_(ctx, kSpv_scan_add, kBindings, sizeof(abi::ScanPush), default_workgroup_size(ctx)) {}

void ScanKernel::record(Recorder& rec, Buffer& data, uint32_t count, std::vector<std::unique_ptr<Buffer>>& scratch) {
  if (count == 0) return;
  const uint32_t per_block = blocks_.workgroup_size() * SCAN_ITEMS_PER_THREAD;
  const uint32_t blocks = (count + per_block - 1) / per_block;
  scratch.push_back(std::make_unique<Buffer>(ctx_, uint64_t(blocks) * sizeof(uint32_t), kStorage));
  Buffer& sums = *scratch.back();
  const Grid grid = grid_for_groups(ctx_, blocks);
  abi::ScanPush push{count, grid.row, 0, 0};
  const Buffer* bufs[] = {&data, &sums};
  rec.dispatch(blocks_, bufs, &push, grid, "scan");
  rec.barrier();
  if (blocks > 1) {
    record(rec, sums, blocks, scratch);
    rec.dispatch(add_, bufs, &push, grid, "scan");
    rec.barrier();
  }
}

}  // namespace mpumesh::vk
