// The isolated reader (core/io/isolated_read.h): a volume comes back from the child as it
// was read; its InputError comes back as itself; its crash, a segmentation fault or an
// abort, and its hang past the time limit are InputErrors that name the file and the
// reader; and the caller goes on.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <cstdlib>
#include <stdexcept>

#include "common/error.h"
#include "io/isolated_read.h"

namespace mpumesh {
namespace {

std::string message_of(const std::function<PlainVolume()>& read) {
  try {
    read_isolated("scan.dcm", "the test reader", read);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(IsolatedRead, TheVolumeComesBackAsRead) {
  PlainVolume v;
  v.dims = {3, 2, 5};
  v.spacing = {0.5, 0.7, 2.0};
  v.origin = {-1, 2, 30};
  v.direction = {0, 1, 0, 1, 0, 0, 0, 0, -1};
  v.modality = "CT";
  v.notes = {"a note", ""};
  for (int i = 0; i < 30; ++i) v.voxels.push_back(float(i) * 1.5f - 7);
  const PlainVolume back = read_isolated("scan.dcm", "the test reader", [&] { return v; });
  EXPECT_EQ(back.dims, v.dims);
  EXPECT_EQ(back.spacing, v.spacing);
  EXPECT_EQ(back.origin, v.origin);
  EXPECT_EQ(back.direction, v.direction);
  EXPECT_EQ(back.modality, v.modality);
  EXPECT_EQ(back.notes, v.notes);
  EXPECT_EQ(back.voxels, v.voxels);
  // A large one (64 MB) too.
  PlainVolume big;
  big.dims = {256, 256, 256};
  big.voxels.assign(size_t(256) * 256 * 256, 3.25f);
  big.voxels.back() = -1;
  EXPECT_EQ(read_isolated("big.nii", "the test reader", [&] { return big; }).voxels, big.voxels);
}

// Voxels that are all int16 travel packed, the others as floats; either way they come
// back bit for bit: int16's ends, and a -0 or a value just past an end, which keep the
// volume in floats.
TEST(IsolatedRead, IntegerVoxelsComeBackBitForBit) {
  auto round_trip = [](const std::vector<float>& voxels) {
    PlainVolume v;
    v.dims = {int64_t(voxels.size()), 1, 1};
    v.voxels = voxels;
    v.notes = {"odd length"};  // the voxels' start does not fall on a multiple of 8 by itself
    const PlainVolume back = read_isolated("ct.nii", "the test reader", [&] { return v; });
    bool same = back.voxels.size() == voxels.size();
    for (size_t i = 0; same && i < voxels.size(); ++i) same = std::memcmp(&back.voxels[i], &voxels[i], sizeof(float)) == 0;
    return same;
  };
  std::vector<float> ct;
  for (int i = 0; i < 70001; ++i) ct.push_back(float(i % 4000 - 1024));
  ct.push_back(-32768.0f);
  ct.push_back(32767.0f);
  EXPECT_TRUE(round_trip(ct));
  for (const float odd : {-0.0f, 32768.0f, -32769.0f, 0.5f}) {
    std::vector<float> v = ct;
    v[12345] = odd;
    EXPECT_TRUE(round_trip(v)) << odd;
  }
  EXPECT_TRUE(round_trip({}));
}

TEST(IsolatedRead, ErrorsCrashesAndHangsComeBackAsErrorsNamingTheFile) {
  EXPECT_EQ(message_of([]() -> PlainVolume { throw InputError("scan.dcm: bad header"); }), "scan.dcm: bad header");
  EXPECT_EQ(message_of([]() -> PlainVolume { throw std::runtime_error("odd"); }), "scan.dcm: odd");
  EXPECT_EQ(message_of([]() -> PlainVolume { std::abort(); }),
            "scan.dcm: the test reader crashed (abort) — the file is probably malformed or of an unsupported kind");
  // (A sanitizer's own handler may turn the fault into an abort.)
  const std::string segv = message_of([]() -> PlainVolume {
    ::raise(SIGSEGV);
    return {};
  });
  EXPECT_EQ(segv.rfind("scan.dcm: the test reader crashed (", 0), 0u) << segv;
  EXPECT_NE(segv.find(") — the file is probably malformed or of an unsupported kind"), std::string::npos) << segv;
  ::setenv("MPUMESH_READER_TIMEOUT", "0.5", 1);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(message_of([]() -> PlainVolume {
              for (;;) ::pause();
            }),
            "scan.dcm: the test reader ran past its time limit of 0.5 s; the file is probably malformed "
            "(MPUMESH_READER_TIMEOUT sets the limit)");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  ::unsetenv("MPUMESH_READER_TIMEOUT");
}

}  // namespace
}  // namespace mpumesh
