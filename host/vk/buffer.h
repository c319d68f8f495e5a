// Storage and uniform buffers. On devices whose memory is the host's (CPU devices such
// as lavapipe, integrated GPUs) buffers are host-visible and written in place; on a
// discrete GPU they live in device-local memory and upload()/download() go through a
// staging buffer and a copy on the queue.
#pragma once

#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include "vk/context.h"

namespace mpumesh::vk {

class Buffer {
 public:
  // kStaging: host-visible (cached where the device offers it) and mapped. Besides
  // staging copies, a kernel may read or write it directly over the bus: small per-call
  // inputs and outputs, which then need no copy submission of their own.
  enum class Kind { kDevice, kStaging };
  Buffer(Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, Kind kind = Kind::kDevice);
  ~Buffer();
  Buffer(Buffer&& o) noexcept;
  Buffer& operator=(Buffer&&) = delete;
  Buffer(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // null unless host-visible

  void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;

  template <class T>
  std::vector<T> read(size_t count, size_t first = 0) const {
    std::vector<T> out(count);
    if (count) download(out.data(), count * sizeof(T), first * sizeof(T));
    return out;
  }

 private:
  Context* ctx_;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

// Usage flags for a compute storage buffer that can be copied both ways.
inline constexpr VkBufferUsageFlags kStorage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
inline constexpr VkBufferUsageFlags kUniform = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

// A host vector as a new storage buffer; an empty one gets one element (Vulkan has no
// buffer of zero bytes).
template <class T, class A>
std::unique_ptr<Buffer> upload_vector(Context& ctx, const std::vector<T, A>& v) {
  const VkDeviceSize bytes = std::max<VkDeviceSize>(v.size() * sizeof(T), sizeof(T));
  auto b = std::make_unique<Buffer>(ctx, bytes, kStorage);
  if (!v.empty()) b->upload(v.data(), v.size() * sizeof(T));
  return b;
}

}  // namespace mpumesh::vk
