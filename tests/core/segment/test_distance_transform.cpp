// The distance transform against brute force, with anisotropic pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "segment/distance_transform.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(DistanceTransform, MatchesBruteForceWithAnisotropicPixels) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const int64_t nx = 5 + int64_t(rng() % 30), ny = 5 + int64_t(rng() % 30);
    const double wx = 0.3 + (rng() % 100) / 50.0, wy = 0.3 + (rng() % 100) / 50.0;
    std::vector<uint8_t> m(size_t(nx * ny));
    for (auto& v : m) v = rng() % 10 == 0;
    for (const uint8_t target : {1, 0}) {  // sparse targets (rows without one), and dense
      const auto d2 = seg::squared_distance_2d(m.data(), nx, ny, target, wx, wy);
      for (int64_t j = 0; j < ny; ++j)
        for (int64_t i = 0; i < nx; ++i) {
          double best = INFINITY;
          for (int64_t b = 0; b < ny; ++b)
            for (int64_t a = 0; a < nx; ++a)
              if (m[size_t(a + nx * b)] == target)
                best = std::min(best, std::pow(wx * (a - i), 2) + std::pow(wy * (b - j), 2));
          ASSERT_NEAR(d2[size_t(i + nx * j)], best, 1e-4 * (1 + best)) << "trial " << trial;
        }
    }
  }
  std::vector<uint8_t> empty(16, 0);
  EXPECT_TRUE(std::isinf(seg::squared_distance_2d(empty.data(), 4, 4, 1)[5]));
}

}  // namespace
}  // namespace mpumesh
