// The slice-phase modulation of |H|: small on a smooth sphere, large on one whose radius
// ripples with the slices' period (a staircase's signature), and the bins placed by the
// phase within the period.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/slice_phase.h"
#include "test_support.h"

namespace mpumesh {
namespace {

constexpr double kSlice = 2.0;  // mm

TEST(SlicePhase, ASmoothSphereHasLittleModulation) {
  const TriangleMesh sphere = test::icosphere(20, 6);
  const SlicePhase p = slice_phase(sphere, {0.3, -0.2, 0.37}, {0, 0, 1}, kSlice);
  EXPECT_NEAR(p.mean_abs_h, 1 / 20.0, 0.002);
  EXPECT_LT(p.modulation, 0.05);
  int64_t n = 0;
  for (int64_t c : p.bin_vertices) n += c;
  EXPECT_EQ(n, int64_t(sphere.vertices.size()));
}

TEST(SlicePhase, ARippleWithTheSlicesPeriodIsLarge) {
  TriangleMesh m = test::icosphere(20, 6);
  // 0.05 mm of radius, in phase with the slices: H swings by about A (2π / period)².
  for (auto& v : m.vertices) v *= 1 + 0.05 / 20 * std::cos(2 * M_PI * v.z() / kSlice);
  const SlicePhase p = slice_phase(m, {0, 0, 0}, {0, 0, 1}, kSlice);
  EXPECT_GT(p.modulation, 1.0);
  // The same mesh seen with slices of another period: the ripple spreads over every bin.
  EXPECT_LT(slice_phase(m, {0, 0, 0}, {0, 0, 1}, kSlice * 1.37).modulation, 0.5 * p.modulation);
}

}  // namespace
}  // namespace mpumesh
