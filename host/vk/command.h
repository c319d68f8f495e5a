// Records compute work into one command buffer: dispatches with their descriptor sets and
// push constants, a full compute-to-compute barrier between dependent passes, buffer
// copies, and GPU timestamps around each labelled dispatch. submit_and_wait() runs it and
// fills kernel_ms() with the measured time of each label (summed over repeats).
#pragma once

#include <vulkan/vulkan.h>

#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "vk/context.h"

namespace mpumesh::vk {

class Buffer;
class ComputePipeline;

// A dispatch of `invocations` threads as a 2D grid of workgroups when one row of
// workgroups cannot hold them; `row` is the invocation count of one row (for the shader's
// linear index).
struct Grid {
  uint32_t groups_x = 1, groups_y = 1, row = 0;
};
Grid grid_for(const Context& ctx, uint64_t invocations, uint32_t workgroup);
// The same for kernels that index by workgroup (`row_groups` workgroups per row).
Grid grid_for_groups(const Context& ctx, uint64_t groups);

class Recorder {
 public:
  explicit Recorder(Context& ctx);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  void dispatch(ComputePipeline& pipe, std::span<const Buffer* const> buffers, const void* push, Grid grid,
                const std::string& label);
  void barrier();  // compute and transfer writes before compute and transfer reads
  void fill(Buffer& dst, uint32_t value);  // the whole buffer, as 32-bit words
  void copy(const Buffer& src, Buffer& dst, VkDeviceSize bytes, VkDeviceSize src_offset = 0,
            VkDeviceSize dst_offset = 0);
  void submit_and_wait();
  // The same, then each kernel's device time (ms, by label) added to `kernel_ms`.
  void submit_and_wait(std::map<std::string, double>& kernel_ms);

 private:
  Context& ctx_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  uint32_t query_count_ = 0;
  std::vector<std::string> labels_;
  std::vector<std::pair<ComputePipeline*, VkDescriptorSet>> sets_;
  std::map<std::string, double> kernel_ms_;
  bool submitted_ = false;
};

}  // namespace mpumesh::vk
