#include "vk/buffer.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "vk/command.h"
#include "vk/vk_check.h"

namespace mpumesh::vk {

Buffer::Buffer(Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, Kind kind) : ctx_(&ctx) {
  size_ = std::max<VkDeviceSize>(bytes, 16);  // Vulkan forbids empty buffers
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size_;
  bi.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VK_CHECK(vkCreateBuffer(ctx.device(), &bi, nullptr, &buffer_));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
  const bool uma = ctx.info().type == "cpu" || ctx.info().type == "integrated";
  const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  uint32_t type = UINT32_MAX;
  if (kind == Kind::kStaging) {
    type = ctx.memory_type(req.memoryTypeBits, host | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    if (type == UINT32_MAX) type = ctx.memory_type(req.memoryTypeBits, host);
  } else if (uma) {
    type = ctx.memory_type(req.memoryTypeBits, host | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type == UINT32_MAX) type = ctx.memory_type(req.memoryTypeBits, host);
  } else {
    type = ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  }
  if (type == UINT32_MAX) {
    vkDestroyBuffer(ctx.device(), buffer_, nullptr);
    throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT, "no suitable Vulkan memory type for a buffer");
  }
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = type;
  VkResult r = vkAllocateMemory(ctx.device(), &ai, nullptr, &memory_);
  if (r != VK_SUCCESS) {
    vkDestroyBuffer(ctx.device(), buffer_, nullptr);
    throw VulkanError(r, "cannot allocate " + std::to_string(req.size >> 20) + " MiB on the Vulkan device: " +
                             result_name(r));
  }
  VK_CHECK(vkBindBufferMemory(ctx.device(), buffer_, memory_, 0));
  if (kind == Kind::kStaging || uma) VK_CHECK(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

Buffer::Buffer(Buffer&& o) noexcept
    : ctx_(o.ctx_), buffer_(o.buffer_), memory_(o.memory_), size_(o.size_), mapped_(o.mapped_) {
  o.buffer_ = VK_NULL_HANDLE;
  o.memory_ = VK_NULL_HANDLE;
  o.mapped_ = nullptr;
}

Buffer::~Buffer() {
  if (!ctx_) return;
  if (mapped_) vkUnmapMemory(ctx_->device(), memory_);
  if (buffer_) vkDestroyBuffer(ctx_->device(), buffer_, nullptr);
  if (memory_) vkFreeMemory(ctx_->device(), memory_, nullptr);
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (offset + bytes > size_) throw std::out_of_range("Buffer::upload past the end of the buffer");
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    return;
  }
  Buffer staging(*ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, Kind::kStaging);
  std::memcpy(staging.mapped(), data, bytes);
  Recorder rec(*ctx_);
  rec.copy(staging, *this, bytes, 0, offset);
  rec.submit_and_wait();
}

void Buffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (offset + bytes > size_) throw std::out_of_range("Buffer::download past the end of the buffer");
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  Buffer staging(*ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Kind::kStaging);
  Recorder rec(*ctx_);
  rec.copy(*this, staging, bytes, offset, 0);
  rec.submit_and_wait();
  std::memcpy(data, staging.mapped(), bytes);
}

}  // namespace mpumesh::vk
