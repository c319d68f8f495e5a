// The Vulkan instance, the chosen physical device, its logical device with one compute
// queue and a command pool. Device choice: discrete GPU, then integrated, then virtual,
// then CPU (lavapipe), or the index the user gives. With validation on (ContextOptions or
// MPUMESH_VALIDATION=1) the Khronos layer is enabled and every warning or error it
// reports is kept, so that tests can fail on any.
#pragma once

#include <vulkan/vulkan.h>

#include <mutex>
#include <string>
#include <vector>

namespace mpumesh::vk {

struct DeviceInfo {
  int index = 0;
  std::string name, type, driver;
  uint32_t api_version = 0;
  uint64_t device_local_bytes = 0;
  bool has_compute = false;
  bool is_software() const { return type == "cpu"; }
};

struct ContextOptions {
  int device_index = -1;        // -1: choose by type
  bool validation = false;      // also on when MPUMESH_VALIDATION=1
  bool hardware_only = false;   // refuse CPU (software) devices: NoVulkanDevice if none
};

// Devices on this machine; empty when there is no loader or no driver.
std::vector<DeviceInfo> list_devices();
// The index the default choice takes, or -1.
int default_device_index(const std::vector<DeviceInfo>& devices, bool hardware_only);

class Context {
 public:
  explicit Context(const ContextOptions& opt = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkDevice device() const { return device_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkQueue queue() const { return queue_; }
  VkCommandPool command_pool() const { return pool_; }
  const DeviceInfo& info() const { return info_; }
  const VkPhysicalDeviceLimits& limits() const { return limits_; }
  double timestamp_period_ns() const { return timestamp_period_; }
  bool timestamps_supported() const { return timestamps_; }
  // The queue also takes graphics work (the offscreen renderer needs it).
  bool graphics_supported() const { return graphics_; }
  bool validation_enabled() const { return validation_; }

  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags want) const;

  // Validation warnings and errors received so far.
  std::vector<std::string> validation_messages() const;

 private:
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT type,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
  void destroy();

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  DeviceInfo info_;
  VkPhysicalDeviceLimits limits_{};
  VkPhysicalDeviceMemoryProperties mem_props_{};
  double timestamp_period_ = 1.0;
  bool timestamps_ = false;
  bool graphics_ = false;
  bool validation_ = false;
  mutable std::mutex messages_mutex_;
  std::vector<std::string> messages_;
};

}  // namespace mpumesh::vk
