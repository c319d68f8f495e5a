// Vulkan errors as exceptions. VK_CHECK(expr) throws VulkanError with the VkResult, the
// expression, file and line. NoVulkanDevice is its own type so that tools can fall back
// to the CPU and tests can tell "skipped" from "passed".
#pragma once

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace mpumesh::vk {

class VulkanError : public std::runtime_error {
 public:
  VulkanError(VkResult r, const std::string& what) : std::runtime_error(what), result(r) {}
  VkResult result;
};

class NoVulkanDevice : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* result_name(VkResult r);
[[noreturn]] void throw_vk(VkResult r, const char* expr, const char* file, int line);

}  // namespace mpumesh::vk

#define VK_CHECK(expr)                                                      \
  do {                                                                      \
    VkResult vk_check_r_ = (expr);                                          \
    if (vk_check_r_ != VK_SUCCESS)                                          \
      ::mpumesh::vk::throw_vk(vk_check_r_, #expr, __FILE__, __LINE__);      \
  } while (0)
