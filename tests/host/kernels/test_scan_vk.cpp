// The GPU exclusive scan (scan_blocks.comp + scan_add.comp) against std::exclusive_scan,
// on sizes that are not multiples of the block, including several recursion levels.
#include <gtest/gtest.h>

#include <numeric>
#include <random>

#include "kernels/scan_vk.h"
#include "test_support.h"
#include "vk/vk_check.h"

namespace mpumesh {
namespace {

TEST(ScanVk, MatchesStdExclusiveScan) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  vk::Context& ctx = gpu->context();
  vk::ScanKernel scan(ctx);
  std::mt19937 rng(7);
  for (uint32_t n : {1u, 5u, 1023u, 1025u, 70001u, 1100003u}) {
    std::vector<uint32_t> in(n);
    for (auto& x : in) x = rng() % 6;
    vk::Buffer buf(ctx, uint64_t(n) * 4, vk::kStorage);
    buf.upload(in.data(), uint64_t(n) * 4);
    std::vector<std::unique_ptr<vk::Buffer>> scratch;
    vk::Recorder rec(ctx);
    scan.record(rec, buf, n, scratch);
    rec.submit_and_wait();
    std::vector<uint32_t> want(n);
    std::exclusive_scan(in.begin(), in.end(), want.begin(), 0u);
    EXPECT_EQ(buf.read<uint32_t>(n), want) << "n = " << n;
  }
  test::expect_no_validation_messages(*gpu);
}

}  // namespace
}  // namespace mpumesh
