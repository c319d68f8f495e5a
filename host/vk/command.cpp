#include "vk/command.h"

#include <algorithm>
#include <stdexcept>

#include "vk/buffer.h"
#include "vk/pipeline.h"
#include "vk/vk_check.h"

namespace mpumesh::vk {
namespace {
constexpr uint32_t kMaxQueries = 256;
}

Grid grid_for_groups(const Context& ctx, uint64_t groups) {
  const uint64_t max_x = ctx.limits().maxComputeWorkGroupCount[0];
  Grid g;
  g.groups_x = uint32_t(std::clamp<uint64_t>(groups, 1, max_x));
  const uint64_t y = (groups + g.groups_x - 1) / g.groups_x;
  if (y > ctx.limits().maxComputeWorkGroupCount[1]) throw std::length_error("dispatch too large for the device");
  g.groups_y = uint32_t(std::max<uint64_t>(y, 1));
  g.row = g.groups_x;
  return g;
}

Grid grid_for(const Context& ctx, uint64_t invocations, uint32_t workgroup) {
  Grid g = grid_for_groups(ctx, (invocations + workgroup - 1) / workgroup);
  g.row = g.groups_x * workgroup;
  return g;
}

Recorder::Recorder(Context& ctx) : ctx_(ctx) {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = ctx.command_pool();
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(ctx.device(), &ai, &cmd_));
  if (ctx.timestamps_supported()) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = kMaxQueries;
    VK_CHECK(vkCreateQueryPool(ctx.device(), &qi, nullptr, &queries_));
  }
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(cmd_, &bi));
  if (queries_) vkCmdResetQueryPool(cmd_, queries_, 0, kMaxQueries);
}

Recorder::~Recorder() {
  if (!submitted_) {
    // Abandoned (an exception while recording): nothing was submitted, so nothing runs.
    vkEndCommandBuffer(cmd_);
  }
  for (auto& [pipe, set] : sets_) pipe->free_set(set);
  if (queries_) vkDestroyQueryPool(ctx_.device(), queries_, nullptr);
  vkFreeCommandBuffers(ctx_.device(), ctx_.command_pool(), 1, &cmd_);
}

void Recorder::dispatch(ComputePipeline& pipe, std::span<const Buffer* const> buffers, const void* push, Grid grid,
                        const std::string& label) {
  VkDescriptorSet set = pipe.make_set(buffers);
  sets_.push_back({&pipe, set});
  const bool timed = queries_ && query_count_ + 2 <= kMaxQueries;
  if (timed) vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, query_count_);
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.handle());
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.layout(), 0, 1, &set, 0, nullptr);
  if (pipe.push_bytes()) vkCmdPushConstants(cmd_, pipe.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pipe.push_bytes(), push);
  vkCmdDispatch(cmd_, grid.groups_x, grid.groups_y, 1);
  if (timed) {
    vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, query_count_ + 1);
    query_count_ += 2;
    labels_.push_back(label);
  }
}

void Recorder::barrier() {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_UNIFORM_READ_BIT;
  const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  vkCmdPipelineBarrier(cmd_, stages, stages, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

void Recorder::fill(Buffer& dst, uint32_t value) { vkCmdFillBuffer(cmd_, dst.handle(), 0, VK_WHOLE_SIZE, value); }

void Recorder::copy(const Buffer& src, Buffer& dst, VkDeviceSize bytes, VkDeviceSize src_offset,
                    VkDeviceSize dst_offset) {
  VkBufferCopy region{src_offset, dst_offset, bytes};
  vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &region);
}

void Recorder::submit_and_wait() {
  if (submitted_) throw std::logic_error("Recorder submitted twice");
  // Make the last writes visible to the host.
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
  VK_CHECK(vkEndCommandBuffer(cmd_));
  submitted_ = true;
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  VK_CHECK(vkCreateFence(ctx_.device(), &fi, nullptr, &fence));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  VkResult r = vkQueueSubmit(ctx_.queue(), 1, &si, fence);
  if (r == VK_SUCCESS) r = vkWaitForFences(ctx_.device(), 1, &fence, VK_TRUE, UINT64_MAX);
  vkDestroyFence(ctx_.device(), fence, nullptr);
  VK_CHECK(r);
  if (query_count_) {
    std::vector<uint64_t> ts(query_count_);
    VK_CHECK(vkGetQueryPoolResults(ctx_.device(), queries_, 0, query_count_, ts.size() * sizeof(uint64_t), ts.data(),
                                   sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    for (size_t i = 0; i < labels_.size(); ++i)
      kernel_ms_[labels_[i]] += double(ts[2 * i + 1] - ts[2 * i]) * ctx_.timestamp_period_ns() * 1e-6;
  }
}

void Recorder::submit_and_wait(std::map<std::string, double>& kernel_ms) {
  submit_and_wait();
  for (const auto& [label, ms] : kernel_ms_) kernel_ms[label] += ms;
}

}  // namespace mpumesh::vk
