// The Vulkan context: the devices listed and one picked.
#include <gtest/gtest.h>


#include "test_support.h"
#include "vk/vk_check.h"

namespace mpumesh {
namespace {

TEST(VulkanContext, ListsDevicesAndPicksOne) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const auto devs = vk::list_devices();
  ASSERT_FALSE(devs.empty());
  EXPECT_GE(vk::default_device_index(devs, false), 0);
  EXPECT_FALSE(gpu->device().empty());
  // An index past the end is refused with a message naming it.
  vk::ContextOptions opt;
  opt.device_index = int(devs.size()) + 3;
  try {
    vk::Context bad(opt);
    FAIL() << "expected NoVulkanDevice";
  } catch (const vk::NoVulkanDevice& e) {
    EXPECT_NE(std::string(e.what()).find("--device"), std::string::npos);
  }
}

}  // namespace
}  // namespace mpumesh
