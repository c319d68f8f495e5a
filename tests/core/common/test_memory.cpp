#include "common/memory.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"

namespace mpumesh {
namespace {

TEST(Memory, InputBytesCountAFileOrTheFilesOfAFolder) {
  const std::string dir = test::temp_dir("input_bytes");
  std::filesystem::create_directories(dir + "/series/sub");
  std::ofstream(dir + "/series/a.dcm") << std::string(1000, 'a');
  std::ofstream(dir + "/series/b.dcm") << std::string(234, 'b');
  std::ofstream(dir + "/series/sub/c.dcm") << std::string(50, 'c');  // not one of the series' files
  EXPECT_EQ(input_bytes(dir + "/series/a.dcm"), 1000u);
  EXPECT_EQ(input_bytes(dir + "/series"), 1234u);
  EXPECT_EQ(input_bytes(dir + "/none.mha"), 0u);
}

// The probe maps, advises and touches fresh memory both ways; with the kernel's huge pages
// on request it gives a ratio of two measured times, else 0.
TEST(Memory, HugePageProbeMeasuresBothWays) {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(in, mode);
  const double speedup = huge_page_fault_speedup(4ull << 20);
  if (mode.empty() || mode.find("[never]") != std::string::npos) GTEST_SKIP() << "no transparent huge pages: " << mode;
  EXPECT_GT(speedup, 0.01);
  EXPECT_LT(speedup, 1000);
}

}  // namespace
}  // namespace mpumesh
