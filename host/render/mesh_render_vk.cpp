#include "render/mesh_render_vk.h"

#include <cstring>

#include "render_mesh_frag.spv.h"
#include "render_mesh_vert.spv.h"
#include "render/raster_ref.h"
#include "vulkan_backend.h"
#include "vk/buffer.h"
#include "vk/vk_check.h"

namespace mpumesh::vk {
namespace {

constexpr VkFormat kColourFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

// Every handle the drawing creates, destroyed in reverse on every path out.
struct Objects {
  VkDevice dev;
  VkImage images[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
  VkDeviceMemory memory[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
  VkImageView views[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
  VkRenderPass pass = VK_NULL_HANDLE;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VkShaderModule modules[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  explicit Objects(VkDevice d) : dev(d) {}
  ~Objects() {
    if (fence) vkDestroyFence(dev, fence, nullptr);
    if (cmd) vkFreeCommandBuffers(dev, pool, 1, &cmd);
    if (pipeline) vkDestroyPipeline(dev, pipeline, nullptr);
    if (layout) vkDestroyPipelineLayout(dev, layout, nullptr);
    for (VkShaderModule m : modules)
      if (m) vkDestroyShaderModule(dev, m, nullptr);
    if (framebuffer) vkDestroyFramebuffer(dev, framebuffer, nullptr);
    if (pass) vkDestroyRenderPass(dev, pass, nullptr);
    for (int i = 1; i >= 0; --i) {
      if (views[i]) vkDestroyImageView(dev, views[i], nullptr);
      if (images[i]) vkDestroyImage(dev, images[i], nullptr);
      if (memory[i]) vkFreeMemory(dev, memory[i], nullptr);
    }
  }
};

void make_image(Context& ctx, Objects& o, int i, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                uint32_t w, uint32_t h) {
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = format;
  ii.extent = {w, h, 1};
  ii.mipLevels = 1;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = usage;
  ii.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VK_CHECK(vkCreateImage(o.dev, &ii, nullptr, &o.images[i]));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(o.dev, o.images[i], &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (ai.memoryTypeIndex == UINT32_MAX) ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, 0);
  VK_CHECK(vkAllocateMemory(o.dev, &ai, nullptr, &o.memory[i]));
  VK_CHECK(vkBindImageMemory(o.dev, o.images[i], o.memory[i], 0));
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = o.images[i];
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {aspect, 0, 1, 0, 1};
  VK_CHECK(vkCreateImageView(o.dev, &vi, nullptr, &o.views[i]));
}

VkShaderModule make_module(VkDevice dev, const uint32_t* code, size_t bytes) {
  VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  mi.codeSize = bytes;
  mi.pCode = code;
  VkShaderModule m = VK_NULL_HANDLE;
  VK_CHECK(vkCreateShaderModule(dev, &mi, nullptr, &m));
  return m;
}

void make_pass(Objects& o, uint32_t w, uint32_t h) {
  VkAttachmentDescription att[2]{};
  att[0].format = kColourFormat;
  att[0].samples = VK_SAMPLE_COUNT_1_BIT;
  att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  att[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  att[1] = att[0];
  att[1].format = kDepthFormat;
  att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  VkAttachmentReference colour_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &colour_ref;
  sub.pDepthStencilAttachment = &depth_ref;
  // The colour writes finish before the copy to the host reads them.
  VkSubpassDependency dep{};
  dep.srcSubpass = 0;
  dep.dstSubpass = VK_SUBPASS_EXTERNAL;
  dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dep.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dep.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  dep.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo ri{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  ri.attachmentCount = 2;
  ri.pAttachments = att;
  ri.subpassCount = 1;
  ri.pSubpasses = &sub;
  ri.dependencyCount = 1;
  ri.pDependencies = &dep;
  VK_CHECK(vkCreateRenderPass(o.dev, &ri, nullptr, &o.pass));
  VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fi.renderPass = o.pass;
  fi.attachmentCount = 2;
  fi.pAttachments = o.views;
  fi.width = w;
  fi.height = h;
  fi.layers = 1;
  VK_CHECK(vkCreateFramebuffer(o.dev, &fi, nullptr, &o.framebuffer));
}

void make_pipeline(Objects& o, uint32_t w, uint32_t h) {
  o.modules[0] = make_module(o.dev, kSpv_render_mesh_vert, sizeof kSpv_render_mesh_vert);
  o.modules[1] = make_module(o.dev, kSpv_render_mesh_frag, sizeof kSpv_render_mesh_frag);
  VkPushConstantRange pr{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(abi::RenderPush)};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.pushConstantRangeCount = 1;
  li.pPushConstantRanges = &pr;
  VK_CHECK(vkCreatePipelineLayout(o.dev, &li, nullptr, &o.layout));

  VkPipelineShaderStageCreateInfo stages[2]{};
  for (int i = 0; i < 2; ++i) {
    stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[i].stage = i == 0 ? VK_SHADER_STAGE_VERTEX_BIT : VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[i].module = o.modules[i];
    stages[i].pName = "main";
  }
  VkVertexInputBindingDescription bind{0, sizeof(abi::RenderVertex), VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription attrs[3] = {
      {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(abi::RenderVertex, px)},
      {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(abi::RenderVertex, nx)},
      {2, 0, VK_FORMAT_R32_SFLOAT, offsetof(abi::RenderVertex, value)}};
  VkPipelineVertexInputStateCreateInfo vin{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vin.vertexBindingDescriptionCount = 1;
  vin.pVertexBindingDescriptions = &bind;
  vin.vertexAttributeDescriptionCount = 3;
  vin.pVertexAttributeDescriptions = attrs;
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkViewport viewport{0, 0, float(w), float(h), 0, 1};
  VkRect2D scissor{{0, 0}, {w, h}};
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = 1;
  vp.pViewports = &viewport;
  vp.scissorCount = 1;
  vp.pScissors = &scissor;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;  // two-sided: the shader turns the normal to the viewer
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = VK_TRUE;
  ds.depthWriteEnable = VK_TRUE;
  ds.depthCompareOp = VK_COMPARE_OP_LESS;
  VkPipelineColorBlendAttachmentState blend{};
  blend.colorWriteMask =
      VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = 1;
  cb.pAttachments = &blend;
  VkGraphicsPipelineCreateInfo gi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  gi.stageCount = 2;
  gi.pStages = stages;
  gi.pVertexInputState = &vin;
  gi.pInputAssemblyState = &ia;
  gi.pViewportState = &vp;
  gi.pRasterizationState = &rs;
  gi.pMultisampleState = &ms;
  gi.pDepthStencilState = &ds;
  gi.pColorBlendState = &cb;
  gi.layout = o.layout;
  gi.renderPass = o.pass;
  gi.subpass = 0;
  VK_CHECK(vkCreateGraphicsPipelines(o.dev, VK_NULL_HANDLE, 1, &gi, nullptr, &o.pipeline));
}

}  // namespace

render::Image render_mesh(Context& ctx, const render::RenderScene& scene) {
  if (!ctx.graphics_supported())
    throw NoVulkanDevice("the Vulkan device '" + ctx.info().name + "' has no queue that can draw");
  const uint32_t w = uint32_t(scene.width), h = uint32_t(scene.height);
  if (w > ctx.limits().maxFramebufferWidth || h > ctx.limits().maxFramebufferHeight)
    throw NoVulkanDevice("the drawing (" + std::to_string(w) + " x " + std::to_string(h) +
                         ") exceeds the device's framebuffer limit");
  Objects o(ctx.device());
  make_image(ctx, o, 0, kColourFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
             VK_IMAGE_ASPECT_COLOR_BIT, w, h);
  make_image(ctx, o, 1, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT, w, h);
  make_pass(o, w, h);
  make_pipeline(o, w, h);

  const VkDeviceSize vbytes = std::max<VkDeviceSize>(scene.vertices.size() * sizeof(abi::RenderVertex), 16);
  Buffer vertices(ctx, vbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT);
  if (!scene.vertices.empty())
    vertices.upload(scene.vertices.data(), scene.vertices.size() * sizeof(abi::RenderVertex));
  const VkDeviceSize pixels_bytes = VkDeviceSize(w) * h * 4;
  Buffer pixels(ctx, pixels_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);

  o.pool = ctx.command_pool();
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = o.pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(o.dev, &ai, &o.cmd));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(o.cmd, &bi));
  VkClearValue clear[2];
  clear[0].color = {{1.0f, 1.0f, 1.0f, 1.0f}};
  clear[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = o.pass;
  rp.framebuffer = o.framebuffer;
  rp.renderArea = {{0, 0}, {w, h}};
  rp.clearValueCount = 2;
  rp.pClearValues = clear;
  vkCmdBeginRenderPass(o.cmd, &rp, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdBindPipeline(o.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, o.pipeline);
  vkCmdPushConstants(o.cmd, o.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(abi::RenderPush), &scene.push);
  const VkBuffer vb = vertices.handle();
  const VkDeviceSize zero = 0;
  vkCmdBindVertexBuffers(o.cmd, 0, 1, &vb, &zero);
  vkCmdDraw(o.cmd, uint32_t(scene.vertices.size()), 1, 0, 0);
  vkCmdEndRenderPass(o.cmd);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {w, h, 1};
  vkCmdCopyImageToBuffer(o.cmd, o.images[0], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pixels.handle(), 1, &region);
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
  vkCmdPipelineBarrier(o.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       0, 1, &mb, 0, nullptr, 0, nullptr);
  VK_CHECK(vkEndCommandBuffer(o.cmd));
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VK_CHECK(vkCreateFence(o.dev, &fi, nullptr, &o.fence));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &o.cmd;
  VK_CHECK(vkQueueSubmit(ctx.queue(), 1, &si, o.fence));
  VK_CHECK(vkWaitForFences(o.dev, 1, &o.fence, VK_TRUE, UINT64_MAX));

  render::Image img(static_cast<int>(w), static_cast<int>(h));
  pixels.download(img.rgba.data(), pixels_bytes);
  return img;
}

render::Image render_image(ComputeBackend& backend, const render::RenderScene& scene) {
  if (auto* vb = dynamic_cast<VulkanBackend*>(&backend)) return render::finish(render_mesh(vb->context(), scene), scene);
  return render::finish(render::rasterize_ref(scene), scene);
}

}  // namespace mpumesh::vk
