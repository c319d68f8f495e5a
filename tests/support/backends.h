// One test body run on every backend (TEST_P over "cpu" and "gpu"): the CPU path, and the
// Vulkan backend, which skips without a device (fails where MPUMESH_REQUIRE_VULKAN=1).
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "compute/compute_backend.h"
#include "cpu/cpu_backend.h"
#include "test_support.h"

namespace mpumesh::test {

class BackendTest : public ::testing::TestWithParam<std::string> {
 protected:
  // The backend of this instance, or null (why_no_backend() says why).
  ComputeBackend* backend() {
    if (backend_) return backend_.get();
    if (GetParam() == "cpu") {
      backend_ = std::make_unique<CpuBackend>();
    } else {
      auto gpu = try_vulkan(why_);
      if (!gpu) return nullptr;
      vulkan_ = gpu.get();
      backend_ = std::move(gpu);
    }
    return backend_.get();
  }
  const std::string& why_no_backend() const { return why_; }
  // After the body: no validation message from the Vulkan backend.
  void TearDown() override {
    if (vulkan_) expect_no_validation_messages(*vulkan_);
  }

 private:
  std::unique_ptr<ComputeBackend> backend_;
  vk::VulkanBackend* vulkan_ = nullptr;
  std::string why_;
};

}  // namespace mpumesh::test

// Declares `var`, this instance's backend; without a Vulkan device the test skips, or
// fails where MPUMESH_REQUIRE_VULKAN=1.
#define MPUMESH_BACKEND_OR_SKIP(var)                                                          \
  ComputeBackend* var##_ptr = backend();                                                      \
  if (!var##_ptr) {                                                                           \
    if (::mpumesh::test::env_flag("MPUMESH_REQUIRE_VULKAN")) FAIL() << why_no_backend();      \
    GTEST_SKIP() << why_no_backend();                                                         \
  }                                                                                           \
  ComputeBackend& var = *var##_ptr

#define MPUMESH_INSTANTIATE_BACKENDS(suite) \
  INSTANTIATE_TEST_SUITE_P(Backends, suite, ::testing::Values(std::string("cpu"), std::string("gpu")))
