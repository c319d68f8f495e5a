// The targets' grading: the rate of change bounded, as the exact distance along a row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "particles/spacing_gradation.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// Targets with a step (0.5 mm for x < 5, 4 mm beyond) on a 0.5 mm grid: graded, they rise
// from the step at the grade, never exceed what they were, and every pair of neighbours
// keeps the bound; along a row the result is the exact distance to the step.
TEST(SpacingGradation, BoundsTheRateOfChange) {
  std::vector<Eigen::Vector3d> x;
  std::vector<double> t;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      x.emplace_back(0.5 * i, 0.5 * j, 0.01 * ((i * 7 + j * 3) % 5));  // a little off the plane
      t.push_back(0.5 * i < 5 ? 0.5 : 4.0);
    }
  std::vector<double> g = t;
  const size_t lowered = particles::limit_spacing_gradient(x, g, 0.3);
  size_t expect_lowered = 0;
  double worst = 0;
  for (size_t a = 0; a < x.size(); ++a) {
    EXPECT_LE(g[a], t[a]);
    if (t[a] == 0.5) EXPECT_EQ(g[a], 0.5);
    expect_lowered += g[a] < t[a];
    for (size_t b = 0; b < x.size(); ++b)
      if ((x[a] - x[b]).norm() < 1.5 * 0.5) worst = std::max(worst, g[a] - g[b] - 0.3 * (x[a] - x[b]).norm());
  }
  EXPECT_EQ(lowered, expect_lowered);
  EXPECT_LE(worst, 1e-12);
  // Along row j = 0 the bound comes from the step's last point in that row (x = 4.5 mm);
  // the grid's path there zigzags a little in z, which may add a few µm.
  const size_t at = 30 * 40;  // i = 30, x = 15 mm
  EXPECT_NEAR(g[at], 0.5 + 0.3 * (x[at] - x[9 * 40]).norm(), 0.015);
  EXPECT_LT(g[at], 4.0);
  EXPECT_EQ(g[39 * 40], 4.0);  // x = 19.5: 0.5 + 0.3 * 15 = 5 > 4, not bound
}

}  // namespace
}  // namespace mpumesh
