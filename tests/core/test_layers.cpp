// The floors of core/: each folder includes only from its own floor and those below, so
// that the shared value types sit on the ground floor and the stages build on each other
// in one direction (the pipeline on top).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

// Lowest first.
const std::vector<std::string> kFloors = {"common",  "geometry",  "volume", "io",      "compute", "mc",
                                          "segment", "points",    "mpu",    "particles", "mesh",  "tet",     "multi",  "phantom",
                                          "render",  "report",    "cpu",    "pipeline"};

TEST(Layers, CoreFoldersIncludeOnlyDownward) {
  const std::filesystem::path core = std::filesystem::path(MPUMESH_SOURCE_DIR) / "core";
  auto floor_of = [](const std::string& folder) {
    return std::find(kFloors.begin(), kFloors.end(), folder) - kFloors.begin();
  };
  const std::regex include(R"re(#include "([a-z_]+)/[A-Za-z0-9_]+\.h")re");
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(core)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
    const std::string folder = entry.path().parent_path().filename().string();
    ASSERT_LT(floor_of(folder), ptrdiff_t(kFloors.size())) << "core/" << folder << " has no floor";
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    const std::string s = text.str();
    for (std::sregex_iterator m(s.begin(), s.end(), include), end; m != end; ++m) {
      const std::string to = (*m)[1];
      if (to == "shared") continue;  // the shaders' data contracts (shaders/shared)
      EXPECT_LE(floor_of(to), floor_of(folder))
          << entry.path().lexically_relative(core).string() << " includes " << to << "/, a floor above its own";
    }
    ++files;
  }
  EXPECT_GT(files, 100);
}

}  // namespace
