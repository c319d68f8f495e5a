// The .mpu file: round trip, refusal of corrupt and truncated files with a message naming
// the file, and a fit whose bytes do not depend on the thread count (nor its lattice
// cache's races).
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <atomic>

#include <zlib.h>

#include <cstring>

#include "common/error.h"
#include "mpu/mpu_eval_ref.h"
#include "mpu/lattice_cache.h"
#include "mpu/mpu_fit.h"
#include "mpu/mpu_io.h"
#include "test_support.h"

using namespace mpumesh;

namespace {

const mpu::MpuSurface& sphere_surface() {
  static const mpu::MpuSurface s = [] {
    const test::AnalyticShape shape{test::AnalyticShape::kSphere, 10, 10, 10};
    return mpu::fit_mpu(test::sample_shape(shape, 0.5, 1.0, false), {});
  }();
  return s;
}

std::string refusal(const std::string& bytes) {
  try {
    mpu::parse_mpu(bytes, "bad.mpu");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MpuFile, RoundTripKeepsEveryBitAndEveryValue) {
  const auto& s = sphere_surface();
  const std::string bytes = mpu::serialize_mpu(s);
  const mpu::MpuSurface back = mpu::parse_mpu(bytes, "sphere.mpu");
  EXPECT_EQ(mpu::serialize_mpu(back), bytes);
  ASSERT_EQ(back.leaves.size(), s.leaves.size());
  for (const Eigen::Vector3d p : {Eigen::Vector3d(10, 0.3, 0.2), Eigen::Vector3d(0.1, -9.7, 2.0),
                                  Eigen::Vector3d(1, 2, 3)}) {
    const auto a = mpu::evaluate_hessian(s, p), b = mpu::evaluate_hessian(back, p);
    EXPECT_EQ(a.f, b.f);
    EXPECT_EQ(a.g, b.g);
    EXPECT_EQ(a.Hb, b.Hb);
    EXPECT_EQ(a.H, b.H);
  }
  const std::string path = ::testing::TempDir() + "/round.mpu";
  mpu::write_mpu(s, path);
  EXPECT_EQ(mpu::serialize_mpu(mpu::read_mpu(path)), bytes);
}

// Version 1 files (19 coefficients a leaf, kinds 0-2) are still read: the sphere's leaves
// written so (none uses terms 19-21) read back to the same surface.
TEST(MpuFile, ReadsVersionOneFiles) {
  const auto& s = sphere_surface();
  for (const auto& l : s.leaves) ASSERT_EQ(l.coeffs[19] == 0 && l.coeffs[20] == 0 && l.coeffs[21] == 0, true);
  const std::string v2 = mpu::serialize_mpu(s);
  constexpr size_t kHeader = 120, kHead = 13 * 8, kTail = 8;
  std::string v1 = v2.substr(0, kHeader);
  v1[8] = 1;
  size_t at = kHeader;
  for (size_t i = 0; i < s.leaves.size(); ++i) {
    v1 += v2.substr(at, kHead + 19 * 8);
    v1 += v2.substr(at + kHead + 22 * 8, kTail);
    at += kHead + 22 * 8 + kTail;
  }
  v1 += v2.substr(at, v2.size() - 4 - at);
  const uint32_t crc = uint32_t(crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(v1.data()), uInt(v1.size())));
  v1.append(reinterpret_cast<const char*>(&crc), 4);
  const mpu::MpuSurface back = mpu::parse_mpu(v1, "v1.mpu");
  EXPECT_EQ(mpu::serialize_mpu(back), v2);
}

TEST(MpuFile, RefusesTruncatedCorruptAndForeignFiles) {
  const std::string good = mpu::serialize_mpu(sphere_surface());
  EXPECT_NE(refusal("").find("empty"), std::string::npos);
  // Every truncation point in the header, and some in the body.
  for (size_t n : {size_t(1), size_t(7), size_t(8), size_t(12), size_t(40), size_t(71), size_t(72), size_t(119), size_t(120), size_t(500),
                   good.size() / 2, good.size() - 1}) {
    const std::string m = refusal(good.substr(0, n));
    EXPECT_NE(m.find("bad.mpu"), std::string::npos) << n;
    EXPECT_TRUE(m.find("truncated") != std::string::npos || m.find("magic") != std::string::npos) << n << ": " << m;
  }
  EXPECT_NE(refusal(good + "x").find("past the end"), std::string::npos);
  // One flipped bit anywhere after the header is caught by the CRC.
  for (size_t at : {size_t(130), good.size() / 3, good.size() - 10}) {
    std::string bad = good;
    bad[at] = char(bad[at] ^ 0x10);
    EXPECT_NE(refusal(bad).find("CRC"), std::string::npos) << at;
  }
  std::string text = good;
  text.replace(4, 2, "\n");  // a CRLF -> LF conversion
  EXPECT_NE(refusal(text).find("magic"), std::string::npos);
  EXPECT_NE(refusal("ply\nformat ascii 1.0\n").find("magic"), std::string::npos);
  std::string v3 = good;
  v3[8] = 3;
  EXPECT_NE(refusal(v3).find("version 3"), std::string::npos);
  // A huge leaf count is refused from the size, before any allocation.
  std::string huge = good;
  const uint32_t big = 0xFFFFFFFFu;
  std::memcpy(&huge[48], &big, 4);
  EXPECT_NE(refusal(huge).find("truncated"), std::string::npos);
  EXPECT_THROW(mpu::read_mpu(::testing::TempDir() + "/no-such.mpu"), InputError);
}

TEST(MpuFile, RefusesOutOfRangeValuesEvenWithAGoodCrc) {
  const auto& s = sphere_surface();
  auto with = [&](auto change) {
    mpu::MpuSurface t = s;
    change(t);
    return refusal(mpu::serialize_mpu(t));
  };
  EXPECT_NE(with([](mpu::MpuSurface& t) { t.leaves[3].radius = -1; }).find("radius"), std::string::npos);
  EXPECT_NE(with([](mpu::MpuSurface& t) { t.leaves[0].coeffs[4] = std::nan(""); }).find("non-finite"),
            std::string::npos);
  EXPECT_NE(with([](mpu::MpuSurface& t) { t.leaves[1].kind = mpu::FitKind(7); }).find("kind"), std::string::npos);
  EXPECT_NE(with([](mpu::MpuSurface& t) { t.grid.leaf_ids[0] = uint32_t(t.leaves.size()); }).find("names leaf"),
            std::string::npos);
  EXPECT_NE(with([](mpu::MpuSurface& t) { t.box_size = 0; }).find("size"), std::string::npos);
}

TEST(MpuFit, SameBytesWhateverTheThreadCount) {
  const test::AnalyticShape shape{test::AnalyticShape::kTorus, 12, 4, 4};
  const PointCloud cloud = test::sample_shape(shape, 0.5, 1.0, false);
  std::string one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = mpu::serialize_mpu(mpu::fit_mpu(cloud, {}));
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    many = mpu::serialize_mpu(mpu::fit_mpu(cloud, {}));
  }
  EXPECT_GT(one.size(), 1000u);
  EXPECT_TRUE(one == many) << "fits differ between 1 and 4 threads";
}

// Threads asking for the same keys at once get each key's value, computed about once a
// key; past its size the table still answers (computing again), and a reset empties it.
TEST(MpuFit, LatticeCacheAnswersEveryKeyUnderContention) {
  auto value = [](uint64_t k) { return k % 7 == 0 ? std::nan("") : std::sqrt(double(k)) - 40.0; };
  auto same = [](double a, double b) { return std::isnan(a) ? std::isnan(b) : a == b; };
  mpu::LatticeCache cache;
  for (const size_t keys : {size_t(3000), size_t(200000)}) {  // within the size; far past it
    cache.reset(3000);
    std::atomic<int64_t> computed{0}, wrong{0};
    tbb::parallel_for(size_t(0), 4 * keys, [&](size_t i) {
      const uint64_t k = (i * 2654435761u) % keys;  // every key four times, interleaved
      const double v = cache.get(k, [&] {
        ++computed;
        return value(k);
      });
      if (!same(v, value(k))) ++wrong;
    });
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_GE(computed.load(), int64_t(keys));
    if (keys == 3000) {
      // Every value stored: asked again, none is computed. (How many were computed twice
      // depends on the threads' timing: a thread that finds a key pending computes it too.)
      int64_t again = 0;
      for (uint64_t k = 0; k < keys; ++k) cache.get(k, [&] { return double(++again); });
      EXPECT_EQ(again, 0) << "the cache did not keep the values";
    } else {
      EXPECT_GT(computed.load(), int64_t(keys) + 100000) << "a full table cannot have cached them all";
    }
  }
  cache.reset(3000);
  int64_t after_reset = 0;
  for (uint64_t k = 0; k < 3000; ++k) cache.get(k, [&] { return double(++after_reset); });
  EXPECT_EQ(after_reset, 3000);
  EXPECT_EQ(cache.get(5, [] { return -1.0; }), 6.0);  // the value stored after the reset
}

// find answers what get stored (NaN too), and nothing for keys never stored or before a
// table exists; the fit reads the level above's table so.
TEST(MpuFit, LatticeCacheFindsOnlyStoredKeys) {
  mpu::LatticeCache cache;
  double v = 1;
  EXPECT_FALSE(cache.find(3, v));
  cache.reset(100);
  for (uint64_t k = 0; k < 100; k += 2) cache.get(k, [&] { return k == 10 ? std::nan("") : double(k) / 3; });
  for (uint64_t k = 0; k < 100; ++k) {
    const bool found = cache.find(k, v);
    EXPECT_EQ(found, k % 2 == 0) << k;
    if (found && k == 10) EXPECT_TRUE(std::isnan(v));
    else if (found) EXPECT_EQ(v, double(k) / 3) << k;
  }
  cache.reset(100);
  EXPECT_FALSE(cache.find(4, v));
}
