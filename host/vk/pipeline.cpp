#include "vk/pipeline.h"

#include <algorithm>

#include "vk/buffer.h"
#include "vk/vk_check.h"

namespace mpumesh::vk {

namespace {
constexpr uint32_t kSetsPerPool = 64;
}

uint32_t default_workgroup_size(const Context& ctx) {
  return std::min<uint32_t>({256u, ctx.limits().maxComputeWorkGroupSize[0], ctx.limits().maxComputeWorkGroupInvocations});
}

ComputePipeline::ComputePipeline(Context& ctx, std::span<const uint32_t> spirv, std::vector<Binding> bindings,
                                 uint32_t push_bytes, uint32_t workgroup_size)
    : ctx_(ctx), bindings_(std::move(bindings)), push_bytes_(push_bytes), workgroup_(workgroup_size) {
  VkDevice dev = ctx.device();
  VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  mi.codeSize = spirv.size_bytes();
  mi.pCode = spirv.data();
  VK_CHECK(vkCreateShaderModule(dev, &mi, nullptr, &module_));
  std::vector<VkDescriptorSetLayoutBinding> lb;
  std::vector<VkDescriptorPoolSize> sizes;
  for (const auto& b : bindings_) {
    lb.push_back({b.binding, b.type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    sizes.push_back({b.type, kSetsPerPool});
  }
  VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  li.bindingCount = uint32_t(lb.size());
  li.pBindings = lb.data();
  VK_CHECK(vkCreateDescriptorSetLayout(dev, &li, nullptr, &set_layout_));
  VkPushConstantRange pr{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes_};
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &set_layout_;
  pli.pushConstantRangeCount = push_bytes_ ? 1 : 0;
  pli.pPushConstantRanges = &pr;
  VK_CHECK(vkCreatePipelineLayout(dev, &pli, nullptr, &layout_));
  VkSpecializationMapEntry entry{0, 0, sizeof(uint32_t)};
  VkSpecializationInfo spec{1, &entry, sizeof(uint32_t), &workgroup_};
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = module_;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = &spec;
  ci.layout = layout_;
  VK_CHECK(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline_));
  VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pi.maxSets = kSetsPerPool;
  pi.poolSizeCount = uint32_t(sizes.size());
  pi.pPoolSizes = sizes.data();
  VK_CHECK(vkCreateDescriptorPool(dev, &pi, nullptr, &pool_));
}

ComputePipeline::~ComputePipeline() {
  VkDevice dev = ctx_.device();
  if (pool_) vkDestroyDescriptorPool(dev, pool_, nullptr);
  if (pipeline_) vkDestroyPipeline(dev, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(dev, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(dev, set_layout_, nullptr);
  if (module_) vkDestroyShaderModule(dev, module_, nullptr);
}

VkDescriptorSet ComputePipeline::make_set(std::span<const Buffer* const> buffers) {
  if (buffers.size() != bindings_.size())
    throw std::invalid_argument("ComputePipeline::make_set: wrong number of buffers");
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pool_;
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &set_layout_;
  VkDescriptorSet set;
  VK_CHECK(vkAllocateDescriptorSets(ctx_.device(), &ai, &set));
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (size_t i = 0; i < buffers.size(); ++i) {
    infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = bindings_[i].binding;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = bindings_[i].type;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(ctx_.device(), uint32_t(writes.size()), writes.data(), 0, nullptr);
  return set;
}

void ComputePipeline::free_set(VkDescriptorSet set) { vkFreeDescriptorSets(ctx_.device(), pool_, 1, &set); }

}  // namespace mpumesh::vk
