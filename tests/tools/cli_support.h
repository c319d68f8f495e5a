// Running the mpumesh program from the CLI tests: its exit code and output, a phantom
// volume, and the check of a run that must fail cleanly.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "io/volume_io.h"
#include "test_support.h"

namespace mpumesh {

struct Result {
  int code = -1;
  std::string out;  // stdout and stderr
};

// `env`: variable assignments put before the program, e.g. "MPUMESH_MEMORY_LIMIT_GIB=1".
inline Result run(const std::string& args, const std::string& env = "") {
  Result r;
  const std::string cmd = env + " " + std::string(MPUMESH_BIN) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

using test::ball_phantom;

// A run that must fail: exit 1, one "mpumesh: error:" line containing `words`, `out` not
// created, and no temporary (.partial) file left beside it.
inline void expect_failure(const std::string& args, const std::string& words, const std::string& out,
                           const std::string& env = "") {
  const Result r = run(args, env);
  EXPECT_EQ(r.code, 1) << args << "\n" << r.out;
  EXPECT_NE(r.out.find("mpumesh: error:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(words), std::string::npos) << "want '" << words << "' in: " << r.out;
  EXPECT_FALSE(std::filesystem::exists(out)) << args;
  const auto dir = std::filesystem::path(out).parent_path();
  if (std::filesystem::is_directory(dir))
    for (auto& e : std::filesystem::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
}

}  // namespace mpumesh
