// A compute pipeline built from embedded SPIR-V: its descriptor-set layout (binding i of
// the type given), a push-constant range, and the workgroup size as specialisation
// constant 0. Descriptor sets are allocated per dispatch from the pipeline's own pool and
// freed by the Recorder once the work has finished.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "vk/context.h"

namespace mpumesh::vk {

class Buffer;

struct Binding {
  uint32_t binding;
  VkDescriptorType type;
};

class ComputePipeline {
 public:
  ComputePipeline(Context& ctx, std::span<const uint32_t> spirv, std::vector<Binding> bindings,
                  uint32_t push_bytes, uint32_t workgroup_size);
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  uint32_t workgroup_size() const { return workgroup_; }
  uint32_t push_bytes() const { return push_bytes_; }

  // A set with buffers[i] at bindings_[i].
  VkDescriptorSet make_set(std::span<const Buffer* const> buffers);
  void free_set(VkDescriptorSet set);

 private:
  Context& ctx_;
  std::vector<Binding> bindings_;
  uint32_t push_bytes_, workgroup_;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
};

// The workgroup size used when the kernel does not ask for another: 256, or the device
// limit when it is lower.
uint32_t default_workgroup_size(const Context& ctx);

}  // namespace mpumesh::vk
